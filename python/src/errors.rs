//! Python exceptions of the package and the conversion of host errors into them: bad input becomes
//! `ValueError` with the host's message (which names the file, field, joint or slice); a failure of
//! the link to a board becomes `dbot.BoardError`.

use pyo3::exceptions::{PyException, PyValueError};
use pyo3::{PyErr, create_exception};

create_exception!(
    dbot,
    DbotError,
    PyException,
    "Base class of the errors raised by dbot."
);
create_exception!(
    dbot,
    BoardError,
    DbotError,
    "The link to a board failed: it vanished, did not answer, or refused a request (the message says which port and request)."
);

create_exception!(
    dbot,
    TrialFaulted,
    DbotError,
    "The board stopped the robot on a fault during Board.record_trial (a servo missing, stuck or overloaded, a setpoint timeout, an emergency stop): the trial is kept with outcome 'faulted' (trial.json's 'fault' names the fault, joint and bus cycle), and the message names the trial folder."
);

/// Bad input: the message of the host error, unchanged.
pub fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// A link failure.
pub fn board_error(e: impl std::fmt::Display) -> PyErr {
    BoardError::new_err(e.to_string())
}

/// A refusal of a rule that protects the robot (`board::rules`): `ValueError` with the library's
/// words, the ones `dbot` prints; a link failure on the way is `dbot.BoardError`.
pub fn rule_error(e: ::board::rules::RuleError) -> PyErr {
    match e {
        ::board::rules::RuleError::Link(e) => board_error(e),
        other => value_error(other),
    }
}

/// Shows what an override let through as a `UserWarning`, in the library's words.
pub fn warn_overridden(
    py: pyo3::Python<'_>,
    warning: Option<&::board::rules::Overridden>,
) -> pyo3::PyResult<()> {
    if let Some(w) = warning {
        let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
        let msg = std::ffi::CString::new(w.to_string()).map_err(value_error)?;
        PyErr::warn(py, &category, &msg, 1)?;
    }
    Ok(())
}
