//! The scene made of the blocks read: the settings over the base conventions, the materials
//! bound by name (SIMRenderer's grey default for a name none has), objects and lights in file
//! order within lumiere's limits.

use super::keywords::{DEFAULT_SEED, grey_default};
use super::{Parsed, Raw, Reader};
use crate::conventions::{Conventions, SamplePosition};
use crate::limits;
use crate::material::Material;
use crate::scene::{Object, ObjectNames, Scene, SceneError, Settings};
use glam::DVec3;
use std::collections::BTreeMap;

impl<'a> Reader<'a> {
    /// The scene: materials bound by name, objects and lights in file order, the settings
    /// over `base`'s conventions.
    pub(super) fn build(mut self, raw: Raw, base: Conventions) -> Result<Parsed, SceneError> {
        let camera = raw.camera.unwrap_or_default();
        let (width, height) = raw.viewport.map_or((500, 500), |v| (v.width, v.height));
        let r = raw.raytracer.unwrap_or_default();
        let mut conventions = base;
        if let Some(p) = r.pixel_coordinate {
            conventions.sample_position = p;
        }
        if let Some(near) = camera.near {
            conventions.near = near;
        }
        if let Some(far) = camera.far {
            conventions.far = far;
        }
        if let Some((n, place)) = &r.sampling
            && *n > 1
            && conventions.sample_position != SamplePosition::Jittered
        {
            self.warn(
                place,
                format!("sampling {n} without pixel_coordinate random traces the same ray {n} times"),
            );
        }
        let settings = Settings {
            width,
            height,
            samples_per_pixel: r.sampling.map_or(1, |(n, _)| n),
            seed: self.seed.unwrap_or(DEFAULT_SEED),
            depth: r.depth.unwrap_or(1),
            shading: r.shading.unwrap_or_default(),
            shadows: true,
            background: DVec3::ZERO,
            color_normalization: r.color_normalization,
            adaptive_threshold: self.adaptive_threshold.unwrap_or(0.0),
            conventions,
            // SIMRenderer has no photon pass.
            caustics: None,
        };
        let highlight = conventions.default_highlight.metal();
        // The materials: the first definition of each name, then the names used but not
        // defined (SIMRenderer's grey default), "default" first and the others sorted, as
        // the TOML format orders them.
        let mut defined: BTreeMap<String, (Material, bool)> = BTreeMap::new();
        for entry in raw.materials {
            if defined.contains_key(&entry.name) {
                let m = format!(
                    "a material named {:?} is already defined; SIMRenderer keeps the first",
                    entry.name
                );
                self.problem(&entry.at, m, "this one is skipped")?;
                continue;
            }
            let mut material = entry.material;
            if !entry.metal_given {
                material.metal = highlight;
            }
            defined.insert(entry.name, (material, entry.metal_given));
        }
        let mut named = defined.clone();
        for s in raw.shapes.iter().filter(|s| s.model.is_none()) {
            if !named.contains_key(&s.material) {
                let hint = match defined.keys().find(|n| n.trim() == s.material.trim()) {
                    Some(close) => format!(" (note the blanks: a material is named {close:?})"),
                    None if s.material == "none" => {
                        " (a primitive without material_name takes the material named \"none\")".to_string()
                    }
                    None => String::new(),
                };
                self.warn(
                    &s.material_at,
                    format!(
                        "no material is named {:?}{hint}; it gets SIMRenderer's grey default material (ambient 0.2, diffuse 0.6, specular 0.7)",
                        s.material
                    ),
                );
                named.insert(s.material.clone(), (grey_default(), true));
            }
        }
        // Each model's materials, named after it: `MODEL/NAME` (`#2`, `#3`... after a name
        // already taken). Their metal factor shapes no term: they take the conventions'.
        // Each model's name (the base of its objects' names) and its materials' names.
        let mut model_names: Vec<(String, Vec<String>)> = Vec::new();
        for (i, s) in raw.shapes.iter().enumerate() {
            let Some(own) = &s.model else {
                continue;
            };
            let base = s.name.clone().unwrap_or_else(|| format!("model#{i}"));
            let mut taken = Vec::new();
            for (name, material) in &own.materials {
                let wanted = format!("{base}/{name}");
                let unique = (1..)
                    .map(|k| {
                        if k == 1 {
                            wanted.clone()
                        } else {
                            format!("{wanted}#{k}")
                        }
                    })
                    .find(|n| !named.contains_key(n))
                    .unwrap_or(wanted);
                let material = Material {
                    metal: highlight,
                    ..material.clone()
                };
                named.insert(unique.clone(), (material, false));
                taken.push(unique);
            }
            model_names.push((base, taken));
        }
        let mut materials = vec![Material {
            metal: highlight,
            ..Material::default()
        }];
        let mut material_names = vec!["default".to_string()];
        let mut metal_given = vec![false];
        for (name, (material, given)) in named {
            if name == "default" {
                materials[0] = material;
                metal_given[0] = given;
            } else {
                materials.push(material);
                material_names.push(name);
                metal_given.push(given);
            }
        }
        let index_of = |name: &str| material_names.iter().position(|n| n == name).unwrap_or(0) as u32;
        let mut objects = Vec::new();
        let mut names = ObjectNames::default();
        let mut model_names = model_names.into_iter();
        for (i, s) in raw.shapes.into_iter().enumerate() {
            if objects.len() + s.shapes.len() > limits::MAX_OBJECTS {
                let m = format!("the scene would hold more than {} objects", limits::MAX_OBJECTS);
                self.problem(&s.at, m, "the rest is dropped")?;
                break;
            }
            if let Some(own) = s.model {
                let (base, taken) = model_names.next().unwrap_or_default();
                let indices: Vec<u32> = taken.iter().map(|n| index_of(n)).collect();
                objects.extend(
                    s.shapes
                        .into_iter()
                        .zip(own.of_shape)
                        .enumerate()
                        .map(|(k, (shape, m))| Object {
                            name: names.add(compact_str::format_compact!("{base}/{k}")),
                            shape,
                            material: indices.get(m as usize).copied().unwrap_or(0),
                        }),
                );
            } else {
                let material = index_of(&s.material);
                for shape in s.shapes {
                    objects.push(Object {
                        name: names.add(
                            s.name
                                .clone()
                                .map_or_else(|| compact_str::format_compact!("{}#{i}", shape.kind()), Into::into),
                        ),
                        shape,
                        material,
                    });
                }
            }
        }
        if raw.lights.len() > limits::MAX_LIGHTS {
            let (place, _) = &raw.lights[limits::MAX_LIGHTS];
            let m = format!("at most {} lights", limits::MAX_LIGHTS);
            self.problem(&place.clone(), m, "the rest are dropped")?;
        }
        let lights = raw
            .lights
            .into_iter()
            .take(limits::MAX_LIGHTS)
            .map(|(_, l)| l)
            .collect();
        Ok(Parsed {
            scene: Scene {
                settings,
                camera: camera.spec,
                materials,
                material_names,
                metal_given,
                objects,
                names,
                lights,
            },
            warnings: self.warnings,
        })
    }
}
