//! How `dbot` prints an error that ends a command: the message, then each cause the message does
//! not already say. Library errors often write their source into their own text (`{file}:
//! {source}`) and also hand it on as their source, so printing the whole chain as anyhow does
//! said the cause twice ("Error: X: Y / Caused by: Y", issue #30).

use std::fmt::Write as _;

/// `Error: <message>`, then `Caused by:` and each cause whose text no earlier line contains.
pub fn report(e: &anyhow::Error) -> String {
    let mut said: Vec<String> = vec![e.to_string()];
    for cause in e.chain().skip(1) {
        let text = cause.to_string();
        if !text.is_empty() && !said.iter().any(|s| s.contains(&text)) {
            said.push(text);
        }
    }
    let mut out = format!("Error: {}", said[0]);
    if said.len() > 1 {
        out.push_str("\n\nCaused by:");
        for s in &said[1..] {
            let _ = write!(out, "\n    {s}");
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An error that writes its source into its own text and also hands it on, as many do.
    #[derive(Debug, thiserror::Error)]
    #[error("plan.json: {source}")]
    struct Embeds {
        source: std::io::Error,
    }

    #[test]
    fn a_cause_the_message_already_says_is_not_said_again() {
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "No such file or directory");
        let e = anyhow::Error::new(Embeds { source: io }).context("reading the plan directory p");
        assert_eq!(
            report(&e),
            "Error: reading the plan directory p\n\nCaused by:\n    plan.json: No such file or directory"
        );
    }

    #[test]
    fn a_cause_not_yet_said_is_said_once_in_order() {
        let e = anyhow::anyhow!("innermost")
            .context("middle")
            .context("outer");
        assert_eq!(
            report(&e),
            "Error: outer\n\nCaused by:\n    middle\n    innermost"
        );
        assert_eq!(report(&anyhow::anyhow!("alone")), "Error: alone");
    }
}
