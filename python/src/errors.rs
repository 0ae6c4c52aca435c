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

/// Bad input: the message of the host error, unchanged.
pub fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// A link failure.
pub fn board_error(e: impl std::fmt::Display) -> PyErr {
    BoardError::new_err(e.to_string())
}
