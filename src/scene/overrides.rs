//! Values that replace a loaded scene's own settings (the command line's `--width`,
//! `--height`, `--spp`, `--seed`, `--depth`, `--adaptive-threshold`, `--conventions` and
//! `--convention`), each checked against its limit as the scene file's value would be.

use super::Scene;
use super::rules::adaptive_threshold;
use crate::conventions::Conventions;
use crate::limits;

/// Settings to replace; `None` keeps the scene's value.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Overrides {
    /// Image width in pixels.
    pub width: Option<u32>,
    /// Image height in pixels.
    pub height: Option<u32>,
    /// Samples per pixel.
    pub spp: Option<u32>,
    /// Seed of every random stream.
    pub seed: Option<u64>,
    /// Recursion depth (1 = no secondary rays).
    pub depth: Option<u32>,
    /// Adaptive depth control threshold in 8-bit levels (0 = off).
    pub adaptive_threshold: Option<f64>,
    /// A preset of conventions (`chapter`, `simrenderer`) replacing the scene's.
    pub conventions: Option<String>,
    /// Switches of the conventions set after the preset, as `key=value`.
    pub convention: Vec<String>,
}

impl Overrides {
    /// Replaces the scene's settings, checking each value against its limits (and the
    /// resulting width x height against the pixel limit). An error names the value as its
    /// command-line option, e.g. `--spp: must be in [1, 1024], got 0`; the scene is then
    /// partly changed and should be dropped.
    pub fn apply(&self, scene: &mut Scene) -> Result<(), String> {
        let bad = |flag: &'static str| move |m: String| format!("--{flag}: {m}");
        let s = &mut scene.settings;
        if let Some(w) = self.width {
            limits::check_dimension(w).map_err(bad("width"))?;
            s.width = w;
        }
        if let Some(h) = self.height {
            limits::check_dimension(h).map_err(bad("height"))?;
            s.height = h;
        }
        limits::check_pixel_count(s.width, s.height).map_err(bad("width/--height"))?;
        if let Some(n) = self.spp {
            limits::check_samples(n).map_err(bad("spp"))?;
            s.samples_per_pixel = n;
        }
        if let Some(seed) = self.seed {
            s.seed = seed;
        }
        if let Some(d) = self.depth {
            limits::check_depth(d).map_err(bad("depth"))?;
            s.depth = d;
        }
        if let Some(t) = self.adaptive_threshold {
            s.adaptive_threshold = adaptive_threshold(t).map_err(|m| format!("--adaptive-threshold: {m}, got {t}"))?;
        }
        let mut conventions = match &self.conventions {
            Some(name) => Conventions::preset(name).map_err(bad("conventions"))?,
            None => s.conventions,
        };
        for switch in &self.convention {
            let (key, value) = switch
                .split_once('=')
                .ok_or_else(|| format!("--convention: expected KEY=VALUE, got {switch:?}"))?;
            conventions
                .set(key.trim(), value.trim())
                .map_err(|m| format!("--convention {}: {m}", key.trim()))?;
        }
        scene.set_conventions(conventions);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene() -> Scene {
        crate::figures::base_scene("reference")
    }

    #[test]
    fn values_replace_the_scene_settings() {
        let mut s = scene();
        let o = Overrides {
            width: Some(40),
            height: Some(30),
            spp: Some(6),
            seed: Some(9),
            depth: Some(2),
            adaptive_threshold: Some(0.0),
            conventions: Some("simrenderer".into()),
            convention: vec!["far = 250".into(), "local_weight=remaining".into()],
        };
        o.apply(&mut s).unwrap();
        // The preset, then each switch: SIMRenderer's but for the far limit and the weight.
        let mut want = crate::conventions::Conventions::SIMRENDERER;
        want.far = 250.0;
        want.local_weight = crate::conventions::LocalWeight::Remaining;
        assert_eq!(s.settings.conventions, want);
        // The default material gives no m: its highlight is now the material's colour.
        assert_eq!(s.materials[0].metal, 1.0);
        let t = &s.settings;
        assert_eq!(
            (t.width, t.height, t.samples_per_pixel, t.seed, t.depth),
            (40, 30, 6, 9, 2)
        );
        assert_eq!(t.adaptive_threshold, 0.0);
        // No override keeps everything.
        let before = scene();
        let mut same = before.clone();
        Overrides::default().apply(&mut same).unwrap();
        assert_eq!(same, before);
    }

    #[test]
    fn errors_name_the_option_and_the_range() {
        let err = |o: Overrides| o.apply(&mut scene()).unwrap_err();
        assert_eq!(
            err(Overrides {
                conventions: Some("pov".into()),
                ..Overrides::default()
            }),
            "--conventions: must be \"chapter\" or \"simrenderer\", got \"pov\""
        );
        assert_eq!(
            err(Overrides {
                convention: vec!["refracting".into()],
                ..Overrides::default()
            }),
            "--convention: expected KEY=VALUE, got \"refracting\""
        );
        assert_eq!(
            err(Overrides {
                convention: vec!["near=0".into()],
                ..Overrides::default()
            }),
            "--convention near: must be a finite distance above 0, got 0"
        );
        for spp in [0, 1025] {
            assert_eq!(
                err(Overrides {
                    spp: Some(spp),
                    ..Overrides::default()
                }),
                format!("--spp: must be in [1, 1024], got {spp}")
            );
        }
        assert_eq!(
            err(Overrides {
                width: Some(16384),
                height: Some(16384),
                ..Overrides::default()
            }),
            "--width/--height: width x height must be at most 33554432 pixels, got 16384 x 16384 = 268435456"
        );
        assert_eq!(
            err(Overrides {
                adaptive_threshold: Some(300.0),
                ..Overrides::default()
            }),
            "--adaptive-threshold: must be a finite number in [0, 255], got 300"
        );
        assert_eq!(
            err(Overrides {
                depth: Some(0),
                ..Overrides::default()
            }),
            "--depth: must be in [1, 64] (1 = no secondary rays), got 0"
        );
    }
}
