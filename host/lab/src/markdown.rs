//! Markdown tables as the commands print them: a header row, its rule, one row per item.

/// A table of `header`'s columns and `rows` (each a row's cells, as many as the header's).
pub fn table(header: &[&str], rows: impl IntoIterator<Item = Vec<String>>) -> String {
    let mut s = format!(
        "| {} |\n|{}\n",
        header.join(" | "),
        "---|".repeat(header.len())
    );
    for cells in rows {
        s.push_str(&format!("| {} |\n", cells.join(" | ")));
    }
    s
}

#[cfg(test)]
mod tests {
    #[test]
    fn a_table_has_its_header_its_rule_and_a_line_per_row() {
        let t = super::table(&["a", "b"], [vec!["1".into(), "2".into()]]);
        assert_eq!(t, "| a | b |\n|---|---|\n| 1 | 2 |\n");
    }
}
