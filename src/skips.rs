//! The work the renderer leaves out when a scene does not need it, one named switch per
//! shortcut. Every shortcut is exact — switching it off changes ray counts and time, never a
//! pixel (tests/skips.rs renders each scene with each switch off and compares bytes) — except
//! adaptive depth control, which has its own threshold (`--adaptive`, 0 = off) and a
//! measured error bound. `lumiere render --no-skip NAME` switches one off; `--stats` counts
//! the work each one saved.

/// One shortcut; [`Skip::help`] says what it leaves out.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Skip {
    /// Lights behind the surface.
    BackFacing,
    /// Lights that bring nothing.
    Unlit,
    /// Any-hit shadow rays.
    OpaqueOnly,
    /// Secondary rays of weight 0.
    ZeroWeight,
    /// Area lights: the blockers found once per shading point.
    ShadowCandidates,
    /// Area lights below the horizon.
    Horizon,
    /// Bounding spheres and cones of directions before exact tests.
    BoundingSpheres,
    /// Shading of blocked lights.
    BlockedShading,
}

impl Skip {
    pub const ALL: [Skip; 8] = [
        Skip::BackFacing,
        Skip::Unlit,
        Skip::OpaqueOnly,
        Skip::ZeroWeight,
        Skip::ShadowCandidates,
        Skip::Horizon,
        Skip::BoundingSpheres,
        Skip::BlockedShading,
    ];

    /// The name used on the command line and in `--stats`.
    pub fn name(self) -> &'static str {
        match self {
            Skip::BackFacing => "back-facing",
            Skip::Unlit => "unlit",
            Skip::OpaqueOnly => "opaque-only",
            Skip::ZeroWeight => "zero-weight",
            Skip::ShadowCandidates => "shadow-candidates",
            Skip::Horizon => "horizon",
            Skip::BoundingSpheres => "bounding-spheres",
            Skip::BlockedShading => "blocked-shading",
        }
    }

    /// What the shortcut leaves out, in one paragraph (the command line's help of `--no-skip`).
    pub fn help(self) -> &'static str {
        match self {
            Skip::BackFacing => {
                "No shadow ray (and no shading) for a light whose direction makes N.L <= 0: neither the diffuse nor, \
                 per the slides, the specular term counts there"
            }
            Skip::Unlit => "No shadow ray for a light that brings nothing: outside a spot's cone, or black",
            Skip::OpaqueOnly => {
                "Shadow rays stop at the first opaque hit (any-hit), and the filtered walk over transparent objects \
                 happens only when the scene has some"
            }
            Skip::ZeroWeight => "No reflected or refracted ray when k_r or k_t is 0",
            Skip::ShadowCandidates => {
                "Area lights: the objects that can block any of a shading point's N shadow rays are found once \
                 (those near the hull of the point and the light's bounding sphere)"
            }
            Skip::Horizon => {
                "Area lights: a light wholly below the surface's horizon (its bounding sphere behind the tangent \
                 plane) is passed over without looking at its N points"
            }
            Skip::BoundingSpheres => {
                "Shadow rays meet an object's bounding sphere before its exact (costly) test; for area lights, the \
                 cones of directions from the shading point decide most rays at once: outside the cone of the \
                 bounding sphere a ray misses, inside the cone through a ball within the solid it hits, a plane none \
                 of the segments to the light can cross is not tested, and neither is a convex shading object's own \
                 surface (rays leaving it outward miss it; rays leaving a solid's inside wall towards a light outside \
                 it hit it). In a linearly scanned scene, a camera ray is not tested against an object whose cone of \
                 directions from the eye it leaves, nor a shadow, reflected or refracted ray against a round object \
                 whose bounding sphere it misses"
            }
            Skip::BlockedShading => "Shading terms (specular power, tints) are not evaluated for a fully blocked light",
        }
    }

    /// What the `--stats` count of this skip counts.
    pub fn unit(self) -> &'static str {
        match self {
            Skip::BackFacing | Skip::Unlit => "shadow rays not traced",
            Skip::OpaqueOnly => "filtered walks not done",
            Skip::ZeroWeight => "secondary rays not traced",
            Skip::ShadowCandidates => "object tests not done",
            Skip::Horizon => "light points not looked at",
            Skip::BoundingSpheres => "exact shape tests not done",
            Skip::BlockedShading => "shading terms not evaluated",
        }
    }
}

impl std::str::FromStr for Skip {
    type Err = String;

    /// Parses a [`name`](Skip::name).
    fn from_str(s: &str) -> Result<Self, String> {
        Skip::ALL.into_iter().find(|k| k.name() == s).ok_or_else(|| {
            let names: Vec<&str> = Skip::ALL.iter().map(|k| k.name()).collect();
            format!("unknown shortcut {s:?}; the shortcuts are: {}", names.join(", "))
        })
    }
}

/// The set of shortcuts switched on (all by default).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Skips(u16);

impl Skips {
    pub fn all() -> Skips {
        Skips(Skip::ALL.iter().fold(0, |bits, s| bits | 1 << *s as u16))
    }

    pub fn none() -> Skips {
        Skips(0)
    }

    /// This set without `skip`.
    pub fn without(self, skip: Skip) -> Skips {
        Skips(self.0 & !(1 << skip as u16))
    }

    pub fn on(self, skip: Skip) -> bool {
        self.0 & 1 << skip as u16 != 0
    }
}

impl Default for Skips {
    fn default() -> Self {
        Skips::all()
    }
}

/// Work saved by each shortcut, indexed by `Skip as usize`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Saved(pub [u64; Skip::ALL.len()]);

impl Saved {
    pub fn add(&mut self, o: &Saved) {
        for (a, b) in self.0.iter_mut().zip(o.0) {
            *a += b;
        }
    }

    pub fn count(&mut self, skip: Skip, n: u64) {
        self.0[skip as usize] += n;
    }

    pub fn get(&self, skip: Skip) -> u64 {
        self.0[skip as usize]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sets_switch_one_skip_at_a_time() {
        let all = Skips::all();
        assert!(Skip::ALL.iter().all(|&s| all.on(s)));
        let some = all.without(Skip::Horizon);
        assert!(!some.on(Skip::Horizon));
        assert_eq!(Skip::ALL.iter().filter(|&&s| some.on(s)).count(), Skip::ALL.len() - 1);
        assert!(Skip::ALL.iter().all(|&s| !Skips::none().on(s)));
        // `--no-skip NAME` and `--stats` use one name, and JSON the same.
        for s in Skip::ALL {
            assert_eq!(s.name().parse::<Skip>(), Ok(s));
            assert_eq!(serde_json::to_string(&s).unwrap(), format!("\"{}\"", s.name()));
        }
        assert!(
            "Horizon"
                .parse::<Skip>()
                .unwrap_err()
                .starts_with("unknown shortcut \"Horizon\"; the shortcuts are: back-facing, unlit,")
        );
    }
}
