//! The lab's one error type: what was being done (the file, the experiment, the stage), and the
//! library error underneath as its source, so a CLI printing the chain reads as before and
//! Python gets the same words.

/// Any error the libraries below return.
pub type Source = Box<dyn std::error::Error + Send + Sync>;

/// Why a lab computation failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum LabError {
    /// Bad input or a result that cannot be used, in words naming the place.
    #[error("{0}")]
    Invalid(String),
    /// The caller asked to stop (e.g. Ctrl-C); the words say where and what was kept.
    #[error("{0}")]
    Interrupted(String),
    /// The board stopped the robot on a fault during a recording; the words name the fault, its
    /// joint and cycle, and the trial that keeps the rows up to it.
    #[error("{0}")]
    Faulted(String),
    /// `what` failed because of `source`.
    #[error("{what}")]
    In {
        what: String,
        #[source]
        source: Source,
    },
    /// A library error, as it is.
    #[error(transparent)]
    Library(Source),
}

impl LabError {
    /// `LabError::Invalid` from words.
    pub fn invalid(words: impl Into<String>) -> Self {
        Self::Invalid(words.into())
    }

    /// Every message of the chain, outermost first, joined by `: ` (for a reader without a
    /// chain printer, e.g. a Python exception).
    pub fn chain_text(&self) -> String {
        let mut s = self.to_string();
        let mut cur: Option<&(dyn std::error::Error + 'static)> = std::error::Error::source(self);
        while let Some(e) = cur {
            s.push_str(": ");
            s.push_str(&e.to_string());
            cur = e.source();
        }
        s
    }
}

/// A `Result` with [`LabError`].
pub type Result<T, E = LabError> = std::result::Result<T, E>;

/// Saying what was being done when an error came up.
pub trait Context<T> {
    fn context(self, what: impl Into<String>) -> Result<T>;
    fn with_context<S: Into<String>>(self, what: impl FnOnce() -> S) -> Result<T>;
}

impl<T, E: Into<Source>> Context<T> for std::result::Result<T, E> {
    fn context(self, what: impl Into<String>) -> Result<T> {
        self.map_err(|e| LabError::In {
            what: what.into(),
            source: e.into(),
        })
    }
    fn with_context<S: Into<String>>(self, what: impl FnOnce() -> S) -> Result<T> {
        self.map_err(|e| LabError::In {
            what: what().into(),
            source: e.into(),
        })
    }
}

impl<T> Context<T> for Option<T> {
    fn context(self, what: impl Into<String>) -> Result<T> {
        self.ok_or_else(|| LabError::Invalid(what.into()))
    }
    fn with_context<S: Into<String>>(self, what: impl FnOnce() -> S) -> Result<T> {
        self.ok_or_else(|| LabError::Invalid(what().into()))
    }
}

/// `?` on the libraries' errors: each becomes [`LabError::Library`].
macro_rules! from_library {
    ($($t:ty),* $(,)?) => {
        $(impl From<$t> for LabError {
            fn from(e: $t) -> Self {
                Self::Library(Box::new(e))
            }
        })*
    };
}

from_library!(
    std::io::Error,
    std::fmt::Error,
    csv::Error,
    planner::model::ModelError,
    planner::model::spring::SpringError,
    nix::errno::Errno,
    planner::plan::PlanError,
    planner::terrain::TerrainError,
    planner::dynamics::DynamicsError,
    planner::strain::StrainError,
    planner::plan_dir::PlanDirError,
    planner::analysis::SweepError,
    board::link::LinkError,
    board::rules::RuleError,
    board::files::FileError,
    board::record::CaptureError,
    physics::PhysicsError,
    protocol::gait::TableError,
    report::legs::PlotError,
    report::robot::FigureError,
);

/// Fails with `LabError::Invalid` from format arguments.
#[macro_export]
macro_rules! bail {
    ($($t:tt)*) => {
        return Err($crate::LabError::Invalid(format!($($t)*)))
    };
}
