//! The conventions on which the course's two renderers disagree, as named switches: the
//! chapter's (what lumiere renders by default, and every figure) and SIMRenderer's, the
//! course's Java ray tracer that students complete. Each switch is documented in
//! scenes/README.md; a preset sets them all, and each can then be set on its own
//! (`[conventions]` in a scene file, `--conventions` and `--convention KEY=VALUE` on the
//! command line).

use serde::Serialize;

/// Where in its pixel each sample's camera ray passes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SamplePosition {
    /// A uniformly random point of each cell of the pixel's
    /// [`SampleGrid`](crate::scene::SampleGrid).
    Jittered,
    /// The centers of the sample grid's cells.
    Regular,
    /// The pixel's center, for every sample.
    Center,
    /// The pixel's top-left corner, for every sample.
    Corner,
    /// Its top-right corner, for every sample.
    TopRight,
    /// Its bottom-left corner, for every sample.
    BottomLeft,
    /// Its bottom-right corner, for every sample.
    BottomRight,
}

/// Where a camera ray starts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RayOrigin {
    /// At the eye.
    Eye,
    /// Where it crosses the image plane at distance `near` in front of the eye: nothing
    /// nearer is seen, and `far` is measured from there.
    NearPlane,
}

/// The colour a transparent object filters a shadow ray's light by.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ShadowFilter {
    /// Its colour `S` (chapter 7.4b).
    Color,
    /// `k_t S`.
    KtColor,
}

/// What multiplies the radiance of a refracted ray.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Transmission {
    /// `k_t`.
    Kt,
    /// `k_t S` where the ray enters the object, `k_t` where it leaves.
    KtColorEntering,
}

/// Which transparent objects refract (spawn a refracted ray) at a camera, reflected or
/// refracted ray's hit. Every transparent object filters shadow rays either way.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Refracting {
    /// Every transparent object.
    Transparent,
    /// Closed shapes only (sphere, box, capped cylinder and cone, torus); an open one
    /// (plane, rectangle, disk) is not seen through.
    Closed,
}

impl Refracting {
    /// Whether a transparent object spawns a refracted ray, for a closed shape or not.
    pub fn admits(self, closed: bool) -> bool {
        self == Refracting::Transparent || closed
    }
}

/// Where the refracted ray's weight goes on total internal reflection.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum InternalReflection {
    /// To the reflected ray: it is traced with `k_r + k_t`.
    Reflected,
    /// Nowhere: the refracted energy is lost.
    Dropped,
}

impl InternalReflection {
    /// The weight of the reflected ray at a hit of reflection weight `k_r` and transmission
    /// weight `k_t` where the refracted ray is totally internally reflected: `k_r + k_t`, or
    /// `k_r`.
    pub fn reflected_weight(self, kr: f64, kt: f64) -> f64 {
        match self {
            InternalReflection::Reflected => kr + kt,
            InternalReflection::Dropped => kr,
        }
    }
}

/// What weighs a hit's local illumination (ambient, diffuse and specular terms).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LocalWeight {
    /// 1: the local terms in full, the reflected and refracted rays added.
    One,
    /// `1 - k_r - k_t`: what the reflected and refracted rays do not carry.
    Remaining,
}

/// The highlight colour of a material that gives no metal factor `m`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Highlight {
    /// `m = 0`: the light's colour.
    Plastic,
    /// `m = 1`: the material's colour.
    Metal,
}

impl Highlight {
    /// The metal factor `m` of a material that gives none.
    pub fn metal(self) -> f64 {
        match self {
            Highlight::Plastic => 0.0,
            Highlight::Metal => 1.0,
        }
    }
}

/// Every convention.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Conventions {
    pub sample_position: SamplePosition,
    pub ray_origin: RayOrigin,
    /// Distance from the eye to the image plane (with [`RayOrigin::NearPlane`]).
    pub near: f64,
    /// Farthest hit of a camera ray, from its origin (infinite: no limit).
    pub far: f64,
    pub shadow_filter: ShadowFilter,
    pub transmission: Transmission,
    pub refracting: Refracting,
    pub total_internal_reflection: InternalReflection,
    pub local_weight: LocalWeight,
    pub default_highlight: Highlight,
}

impl Conventions {
    /// Chapter 7.4b's, and every figure's.
    pub const CHAPTER: Conventions = Conventions {
        sample_position: SamplePosition::Jittered,
        ray_origin: RayOrigin::Eye,
        near: 1.0,
        far: f64::INFINITY,
        shadow_filter: ShadowFilter::Color,
        transmission: Transmission::Kt,
        refracting: Refracting::Transparent,
        total_internal_reflection: InternalReflection::Reflected,
        local_weight: LocalWeight::One,
        default_highlight: Highlight::Plastic,
    };

    /// SIMRenderer's (the lab versions' source): the pixel's top-left corner, camera rays
    /// from the near plane at 1 up to 100, shadows filtered by `k_t S`, refracted rays
    /// weighed by `k_t S` entering and `k_t` leaving, closed shapes only refracting, the
    /// refracted energy lost on total internal reflection, unweighted local terms, and
    /// highlights in the material's colour.
    pub const SIMRENDERER: Conventions = Conventions {
        sample_position: SamplePosition::Corner,
        ray_origin: RayOrigin::NearPlane,
        near: 1.0,
        far: 100.0,
        shadow_filter: ShadowFilter::KtColor,
        transmission: Transmission::KtColorEntering,
        refracting: Refracting::Closed,
        total_internal_reflection: InternalReflection::Dropped,
        local_weight: LocalWeight::One,
        default_highlight: Highlight::Metal,
    };

    /// The presets' names, in order.
    pub const PRESETS: [&'static str; 2] = ["chapter", "simrenderer"];

    /// The switches' names, in the order [`Conventions::describe`] lists them.
    pub const KEYS: [&'static str; 10] = [
        "sample_position",
        "ray_origin",
        "near",
        "far",
        "shadow_filter",
        "transmission",
        "refracting",
        "total_internal_reflection",
        "local_weight",
        "default_highlight",
    ];

    /// The preset called `name`.
    pub fn preset(name: &str) -> Result<Conventions, String> {
        match name {
            "chapter" => Ok(Conventions::CHAPTER),
            "simrenderer" => Ok(Conventions::SIMRENDERER),
            other => Err(format!("must be \"chapter\" or \"simrenderer\", got {other:?}")),
        }
    }

    /// The name of the preset these conventions are, or `None` when some switch differs
    /// from both.
    pub fn preset_name(&self) -> Option<&'static str> {
        [Conventions::CHAPTER, Conventions::SIMRENDERER]
            .iter()
            .position(|p| p == self)
            .map(|i| Conventions::PRESETS[i])
    }

    /// Sets the switch `key` to `value` (its name, as [`Conventions::describe`] prints it;
    /// a number for `near` and `far`, `inf` for no far limit); the error says what `key`
    /// or `value` may be.
    pub fn set(&mut self, key: &str, value: &str) -> Result<(), String> {
        fn pick<T: Copy>(value: &str, options: &[(&str, T)]) -> Result<T, String> {
            options
                .iter()
                .find(|(name, _)| *name == value)
                .map(|(_, v)| *v)
                .ok_or_else(|| {
                    let names: Vec<String> = options.iter().map(|(n, _)| format!("{n:?}")).collect();
                    format!("must be {}, got {value:?}", names.join(" or "))
                })
        }
        let distance = |value: &str, what: &str| -> Result<f64, String> {
            let x: f64 = value
                .trim()
                .parse()
                .map_err(|_| format!("must be a number, got {value:?}"))?;
            if x > 0.0 && (x.is_finite() || what == "far") {
                Ok(x)
            } else {
                Err(format!("must be a {what} distance above 0, got {value}"))
            }
        };
        use SamplePosition as S;
        match key {
            "sample_position" => {
                self.sample_position = pick(
                    value,
                    &[
                        ("jittered", S::Jittered),
                        ("regular", S::Regular),
                        ("center", S::Center),
                        ("corner", S::Corner),
                        ("top_right", S::TopRight),
                        ("bottom_left", S::BottomLeft),
                        ("bottom_right", S::BottomRight),
                    ],
                )?
            }
            "ray_origin" => {
                self.ray_origin = pick(value, &[("eye", RayOrigin::Eye), ("near_plane", RayOrigin::NearPlane)])?
            }
            "near" => self.near = distance(value, "finite")?,
            "far" => self.far = distance(value, "far")?,
            "shadow_filter" => {
                self.shadow_filter = pick(
                    value,
                    &[("color", ShadowFilter::Color), ("kt_color", ShadowFilter::KtColor)],
                )?
            }
            "transmission" => {
                self.transmission = pick(
                    value,
                    &[
                        ("kt", Transmission::Kt),
                        ("kt_color_entering", Transmission::KtColorEntering),
                    ],
                )?
            }
            "refracting" => {
                self.refracting = pick(
                    value,
                    &[("transparent", Refracting::Transparent), ("closed", Refracting::Closed)],
                )?
            }
            "total_internal_reflection" => {
                self.total_internal_reflection = pick(
                    value,
                    &[
                        ("reflected", InternalReflection::Reflected),
                        ("dropped", InternalReflection::Dropped),
                    ],
                )?
            }
            "local_weight" => {
                self.local_weight = pick(
                    value,
                    &[("one", LocalWeight::One), ("remaining", LocalWeight::Remaining)],
                )?
            }
            "default_highlight" => {
                self.default_highlight = pick(value, &[("plastic", Highlight::Plastic), ("metal", Highlight::Metal)])?
            }
            other => {
                return Err(format!(
                    "unknown convention {other:?}; the conventions are {}",
                    Conventions::KEYS.join(", ")
                ));
            }
        }
        Ok(())
    }

    /// Every switch and its value, as `set` takes them, in [`Conventions::KEYS`] order.
    pub fn describe(&self) -> Vec<(&'static str, String)> {
        let name = |v: &dyn erased::Named| v.name();
        let distance = |x: f64| {
            if x.is_finite() {
                format!("{x}")
            } else {
                "inf".to_string()
            }
        };
        let values = [
            name(&self.sample_position),
            name(&self.ray_origin),
            distance(self.near),
            distance(self.far),
            name(&self.shadow_filter),
            name(&self.transmission),
            name(&self.refracting),
            name(&self.total_internal_reflection),
            name(&self.local_weight),
            name(&self.default_highlight),
        ];
        Conventions::KEYS.into_iter().zip(values).collect()
    }

    /// The nearer preset (the one fewer switches differ from; SIMRenderer's on a tie) and
    /// the switches that differ from it, as [`Conventions::describe`] lists them.
    pub fn nearer_preset(&self) -> (&'static str, Vec<(&'static str, String)>) {
        let mine = self.describe();
        [
            ("simrenderer", Conventions::SIMRENDERER),
            ("chapter", Conventions::CHAPTER),
        ]
        .into_iter()
        .map(|(name, preset)| {
            let differing = mine
                .iter()
                .zip(preset.describe())
                .filter(|((_, a), (_, b))| a != b)
                .map(|((k, a), _)| (*k, a.clone()))
                .collect::<Vec<_>>();
            (name, differing)
        })
        .min_by_key(|(_, differing)| differing.len())
        .unwrap_or(("chapter", Vec::new()))
    }

    /// One line: the preset's name, or the nearer preset's with the switches that differ
    /// from it.
    pub fn summary(&self) -> String {
        let (preset, differing) = self.nearer_preset();
        if differing.is_empty() {
            return preset.to_string();
        }
        let differing: Vec<String> = differing
            .iter()
            .map(|(key, value)| format!("{key} = {value}"))
            .collect();
        format!("{preset} with {}", differing.join(", "))
    }
}

impl Default for Conventions {
    fn default() -> Self {
        Conventions::CHAPTER
    }
}

/// The snake-case name of a switch's value, as serde writes it.
mod erased {
    pub trait Named {
        fn name(&self) -> String;
    }

    impl<T: serde::Serialize> Named for T {
        fn name(&self) -> String {
            match serde_json::to_value(self) {
                Ok(serde_json::Value::String(s)) => s,
                other => format!("{other:?}"),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn internal_reflection_sends_the_refracted_weight_to_the_reflection_or_drops_it() {
        // k_r 0.25, k_t 0.5: the chapter's reflected ray carries 0.75, SIMRenderer's 0.25.
        assert_eq!(InternalReflection::Reflected.reflected_weight(0.25, 0.5), 0.75);
        assert_eq!(InternalReflection::Dropped.reflected_weight(0.25, 0.5), 0.25);
    }

    #[test]
    fn every_switch_reads_back_what_describe_prints() {
        for preset in [Conventions::CHAPTER, Conventions::SIMRENDERER] {
            let mut rebuilt = if preset == Conventions::CHAPTER {
                Conventions::SIMRENDERER
            } else {
                Conventions::CHAPTER
            };
            for (key, value) in preset.describe() {
                rebuilt.set(key, &value).unwrap();
            }
            assert_eq!(rebuilt, preset);
        }
        assert_eq!(Conventions::CHAPTER.describe()[3], ("far", "inf".to_string()));
        assert_eq!(
            Conventions::SIMRENDERER.describe()[0],
            ("sample_position", "corner".to_string())
        );
    }

    #[test]
    fn presets_and_summaries() {
        assert_eq!(Conventions::preset("simrenderer"), Ok(Conventions::SIMRENDERER));
        assert_eq!(Conventions::default().summary(), "chapter");
        let mut c = Conventions::CHAPTER;
        c.set("shadow_filter", "kt_color").unwrap();
        c.set("far", "100").unwrap();
        assert_eq!(c.preset_name(), None);
        assert_eq!(c.summary(), "chapter with far = 100, shadow_filter = kt_color");
        // SIMRenderer's with two switches of the chapter's is named after SIMRenderer's.
        let mut s = Conventions::SIMRENDERER;
        s.set("sample_position", "center").unwrap();
        s.set("far", "1000").unwrap();
        assert_eq!(s.summary(), "simrenderer with sample_position = center, far = 1000");
        assert_eq!(
            s.nearer_preset(),
            (
                "simrenderer",
                vec![("sample_position", "center".to_string()), ("far", "1000".to_string())]
            )
        );
    }

    #[test]
    fn bad_keys_and_values_say_what_is_allowed() {
        let mut c = Conventions::CHAPTER;
        assert_eq!(
            c.set("refracting", "open"),
            Err("must be \"transparent\" or \"closed\", got \"open\"".to_string())
        );
        assert_eq!(
            c.set("far", "-1"),
            Err("must be a far distance above 0, got -1".to_string())
        );
        assert_eq!(
            c.set("near", "inf"),
            Err("must be a finite distance above 0, got inf".to_string())
        );
        assert!(
            c.set("gamma", "2.2")
                .unwrap_err()
                .starts_with("unknown convention \"gamma\"; the conventions are")
        );
        assert_eq!(
            Conventions::preset("pbrt"),
            Err("must be \"chapter\" or \"simrenderer\", got \"pbrt\"".to_string())
        );
        assert_eq!(c, Conventions::CHAPTER, "a refused value changes nothing");
    }
}
