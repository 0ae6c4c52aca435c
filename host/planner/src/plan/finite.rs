//! A plan or a solved cycle whose numbers are not all finite is an error, never a result: NaN
//! torques used to print as a plan with "peak 0.308 N m" and exit 0 (issue #19). The error names
//! the quantity, the slice and the joint (or foot column) of the first bad value.

/// The first value that is not finite.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error(
    "{what} of {column} at slice {slice} is {value}: the plan is not usable (check the model's masses, lengths and stiffness and the stepping parameters)"
)]
pub struct NonFinite {
    pub what: &'static str,
    pub slice: usize,
    pub column: String,
    pub value: f64,
}

/// Checks `rows[slice][column]`, naming columns with `names` (or their index).
pub fn check_rows(
    what: &'static str,
    rows: &[Vec<f64>],
    names: &[String],
) -> Result<(), NonFinite> {
    for (slice, row) in rows.iter().enumerate() {
        if let Some((c, v)) = row.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(NonFinite {
                what,
                slice,
                column: names
                    .get(c)
                    .cloned()
                    .unwrap_or_else(|| format!("column {c}")),
                value: *v,
            });
        }
    }
    Ok(())
}

/// Angles, velocities and accelerations of every joint at every slice.
pub fn check_plan(plan: &super::Plan) -> Result<(), NonFinite> {
    let names: Vec<String> = plan.model.joints.iter().map(|j| j.name.clone()).collect();
    check_rows("joint angle", &plan.q, &names)?;
    check_rows("joint velocity", &plan.qd, &names)?;
    check_rows("joint acceleration", &plan.qdd, &names)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_bad_value_is_named_with_its_slice_and_column() {
        let rows = vec![vec![0.0, 1.0], vec![2.0, f64::NAN]];
        let names = vec!["LF_ThC1".to_owned(), "LF_ThC2".to_owned()];
        let e = check_rows("torque", &rows, &names).unwrap_err();
        assert_eq!((e.slice, e.column.as_str()), (1, "LF_ThC2"));
        assert!(
            e.to_string()
                .contains("torque of LF_ThC2 at slice 1 is NaN"),
            "{e}"
        );
        assert!(check_rows("torque", &rows[..1], &names).is_ok());
        let inf = vec![vec![f64::INFINITY]];
        assert!(
            check_rows("grf", &inf, &[])
                .unwrap_err()
                .to_string()
                .contains("column 0")
        );
    }
}
