//! [`Substrate`]: the ground a trial walks on, one closed list shared by the trial records and
//! the physics robot's scenes (`physics:TERRAIN+SUBSTRATE`, e.g. `physics:flat+wire-mesh`). The
//! lab's code names sand paper (the paper's trials), wire mesh and an anti-slip mat
//! (../shared/reference/lab-practice.md); `floor` is the bare ground without one. The friction
//! each stands for on the physics robot is the physics crate's (`physics::substrate`).

use serde::{Deserialize, Serialize};

/// The ground the robot walked on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Substrate {
    /// Not said (a real robot's trial without `--substrate`).
    #[default]
    Unspecified,
    /// The bare floor or table, no substrate laid down.
    Floor,
    /// Sand paper (the paper's trials).
    Sandpaper,
    WireMesh,
    AntiSlipMat,
}

/// The substrates a user can name, in the order messages list them.
pub const KNOWN: [Substrate; 4] = [
    Substrate::Floor,
    Substrate::Sandpaper,
    Substrate::WireMesh,
    Substrate::AntiSlipMat,
];

/// A substrate name that is not one of [`KNOWN`].
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SubstrateError {
    #[error("{place}: unknown substrate `{name}` (known: {})", known_names())]
    Unknown { place: String, name: String },
    #[error(
        "substrate {flag} disagrees with port `{port}`, whose scene walks on {scene}: give one of them"
    )]
    Disagrees {
        flag: &'static str,
        port: String,
        scene: &'static str,
    },
}

fn known_names() -> String {
    KNOWN.map(Substrate::name).join(", ")
}

impl Substrate {
    /// The name trial records, READMEs and scenes use.
    pub fn name(self) -> &'static str {
        match self {
            Substrate::Unspecified => "unspecified",
            Substrate::Floor => "floor",
            Substrate::Sandpaper => "sandpaper",
            Substrate::WireMesh => "wire-mesh",
            Substrate::AntiSlipMat => "anti-slip-mat",
        }
    }

    /// The substrate named `name` (one of [`KNOWN`]); `place` names where it was given.
    pub fn parse(name: &str, place: &str) -> Result<Self, SubstrateError> {
        KNOWN
            .into_iter()
            .find(|s| s.name() == name)
            .ok_or_else(|| SubstrateError::Unknown {
                place: place.to_owned(),
                name: name.to_owned(),
            })
    }

    /// A physics scene split into its terrain and substrate: `flat+wire-mesh` is (`flat`,
    /// wire mesh); a scene without `+` walks on [`Substrate::Sandpaper`], the paper's.
    pub fn split_scene(scene: &str) -> Result<(&str, Self), SubstrateError> {
        match scene.split_once('+') {
            None => Ok((scene, Substrate::Sandpaper)),
            Some((terrain, name)) => Ok((terrain, Self::parse(name, &format!("scene `{scene}`"))?)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scenes_name_their_substrate_and_unknown_names_list_the_known_ones() {
        assert_eq!(
            Substrate::split_scene("flat+wire-mesh"),
            Ok(("flat", Substrate::WireMesh))
        );
        assert_eq!(
            Substrate::split_scene("incline:10"),
            Ok(("incline:10", Substrate::Sandpaper))
        );
        let e = Substrate::split_scene("flat+ice").unwrap_err().to_string();
        assert_eq!(
            e,
            "scene `flat+ice`: unknown substrate `ice` (known: floor, sandpaper, wire-mesh, anti-slip-mat)"
        );
        // `unspecified` is what a record says, not a ground to walk on.
        assert!(Substrate::parse("unspecified", "--substrate").is_err());
    }

    #[test]
    fn trial_json_spells_substrates_as_their_names() {
        for s in KNOWN.into_iter().chain([Substrate::Unspecified]) {
            assert_eq!(
                serde_json::to_string(&s).unwrap(),
                format!("\"{}\"", s.name())
            );
        }
    }
}
