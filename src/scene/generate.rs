//! Seeded scene generators (`[[generate]]` tables): many random objects in a box, for
//! benchmarking the intersection cores on scenes far larger than anyone would write by hand.
//! The same table gives the same objects, bit for bit, on any machine and thread count:
//! objects are drawn in chunks of [`CHUNK`], chunk `k` from its own stream keyed by the
//! table's seed and `(table, k)`.

use super::{NameKey, Object};
use crate::math::other_leg;
use crate::sampling::{Purpose, Stream};
use crate::shape::{Cone, Shape, Sphere, Torus, Triangle};
use glam::DVec3;
use rayon::prelude::*;
use std::sync::Arc;

/// Objects drawn from one stream.
pub const CHUNK: usize = 4096;

/// What a generator makes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum GenerateKind {
    /// Spheres.
    Spheres,
    /// Spheres, tori and cones in equal shares (random axes), each within a ball of the
    /// drawn radius.
    Mixed,
    /// Equilateral triangles inscribed in the circle of the drawn radius, in a random plane
    /// turned by a random angle: a triangle soup, its vertices in one shared array.
    Triangles,
}

impl GenerateKind {
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "spheres" => Some(GenerateKind::Spheres),
            "mixed" => Some(GenerateKind::Mixed),
            "triangles" => Some(GenerateKind::Triangles),
            _ => None,
        }
    }
}

/// A validated `[[generate]]` table.
#[derive(Clone, Debug, PartialEq)]
pub struct Generate {
    pub kind: GenerateKind,
    pub count: usize,
    pub seed: u64,
    /// Centers are uniform in the box `[min, max]`.
    pub min: DVec3,
    pub max: DVec3,
    /// Radii (of the ball holding each object) uniform in `[radius.0, radius.1]`.
    pub radius: (f64, f64),
    /// Material indices, one drawn uniformly per object.
    pub materials: Vec<usize>,
}

impl Generate {
    /// The objects of table number `table`, in Z-order of their centers, unnamed (a scene's
    /// tables are named as [`Generate::append_to`] says).
    ///
    /// Objects near in space are then near in memory, as in scenes made by modelling tools
    /// (meshes, grids); drawn in random order, a million objects would make every object
    /// test of a ray a cache miss, for either core.
    pub fn objects(&self, table: usize) -> Vec<Object> {
        let mut objects = Vec::new();
        self.append_to(table, NameKey::UNNAMED, &mut objects);
        objects
    }

    /// Appends [`Generate::objects`] to `objects`, drawing them in place: a million spheres
    /// take their 48 MB once, with 12 bytes an object of sort keys beside them. The `i`-th
    /// object in Z-order takes the name key `first.nth(i)`: `first` from
    /// [`super::ObjectNames::add_table`], which names it `generate[table]#i`
    /// ([`NameKey::UNNAMED`]: all unnamed).
    pub fn append_to(&self, table: usize, first: NameKey, objects: &mut Vec<Object>) {
        let name = |i: usize| if first == NameKey::UNNAMED { first } else { first.nth(i) };
        if self.kind == GenerateKind::Triangles {
            let drawn = self.sorted(table, |s| self.draw_triangle(s));
            // The vertices in one array, in the objects' order.
            let vertices: Arc<[DVec3]> = drawn.iter().flat_map(|(_, points, _)| *points).collect();
            objects.par_extend(drawn.into_par_iter().enumerate().map(|(i, (_, _, material))| {
                let material = material as u32;
                let first = 3 * i as u32;
                let triangle = Triangle::in_mesh(&vertices, [first, first + 1, first + 2]);
                Object {
                    name: name(i),
                    shape: Shape::Triangle(triangle.expect("three vertices per triangle")),
                    material,
                }
            }));
            return;
        }
        let start = objects.len();
        let placeholder = Object {
            name: NameKey::UNNAMED,
            shape: Shape::Sphere(Sphere::new(DVec3::ZERO, 1.0)),
            material: 0,
        };
        objects.resize(start + self.count, placeholder);
        let drawn = &mut objects[start..];
        let mut codes = vec![0u64; self.count];
        drawn
            .par_chunks_mut(CHUNK)
            .zip(codes.par_chunks_mut(CHUNK))
            .enumerate()
            .for_each(|(k, (objects, codes))| {
                let mut s = self.stream(table, k);
                for (object, code) in objects.iter_mut().zip(codes) {
                    let (z, shape, material) = self.draw(&mut s);
                    (*code, object.shape, object.material) = (z, shape, material as u32);
                }
            });
        // Stable: equal codes keep the drawing order, so the order is fully determined.
        let mut order: Vec<u32> = (0..self.count as u32).collect();
        order.par_sort_by_key(|&i| codes[i as usize]);
        gather_in_place(drawn, &order);
        drawn
            .par_iter_mut()
            .enumerate()
            .for_each(|(i, object)| object.name = name(i));
    }

    /// The stream of chunk `k` of table `table`.
    fn stream(&self, table: usize, k: usize) -> Stream {
        Stream::new(self.seed, Purpose::Generator, ((table as u64) << 32) | k as u64)
    }

    /// The drawn items with their Z-order codes, sorted by code.
    fn sorted<T: Send>(
        &self,
        table: usize,
        draw: impl Fn(&mut Stream) -> (u64, T, usize) + Sync,
    ) -> Vec<(u64, T, usize)> {
        let mut drawn: Vec<(u64, T, usize)> = (0..self.count.div_ceil(CHUNK))
            .into_par_iter()
            .flat_map_iter(|k| {
                let mut s = self.stream(table, k);
                let end = ((k + 1) * CHUNK).min(self.count);
                (k * CHUNK..end).map(|_| draw(&mut s)).collect::<Vec<_>>()
            })
            .collect();
        // Stable: equal codes keep the drawing order, so the order is fully determined.
        drawn.par_sort_by_key(|(code, _, _)| *code);
        drawn
    }

    /// 63-bit Morton code of `p`: 21 bits per axis of its place in the region.
    fn z_order(&self, p: DVec3) -> u64 {
        let unit = (p - self.min) / (self.max - self.min);
        let q = unit
            .to_array()
            .map(|x| (x.clamp(0.0, 1.0) * ((1 << 21) - 1) as f64) as u64);
        // Spreads the 21 bits of x to every third bit.
        let spread = |mut x: u64| {
            x &= 0x1f_ffff;
            x = (x | x << 32) & 0x1f00000000ffff;
            x = (x | x << 16) & 0x1f0000ff0000ff;
            x = (x | x << 8) & 0x100f00f00f00f00f;
            x = (x | x << 4) & 0x10c30c30c30c30c3;
            (x | x << 2) & 0x1249249249249249
        };
        spread(q[0]) | spread(q[1]) << 1 | spread(q[2]) << 2
    }

    /// Where an object goes: its center, the radius of its ball and its material.
    fn place(&self, u: &mut dyn FnMut() -> f64) -> (DVec3, f64, usize) {
        let c = DVec3::new(u(), u(), u());
        let center = self.min + (self.max - self.min) * c;
        let (lo, hi) = self.radius;
        let r = lo + (hi - lo) * u();
        let material = self.materials[((u() * self.materials.len() as f64) as usize).min(self.materials.len() - 1)];
        (center, r, material)
    }

    /// One object: center, radius, material, then for `mixed` the kind and an axis; with
    /// the Z-order code of its center.
    fn draw(&self, s: &mut Stream) -> (u64, Shape, usize) {
        let mut u = || s.next_f64();
        let (center, r, material) = self.place(&mut u);
        let shape = match self.kind {
            GenerateKind::Mixed => {
                let which = u();
                let axis = direction(&mut u);
                if which < 1.0 / 3.0 {
                    Shape::Sphere(Sphere::new(center, r))
                } else if which < 2.0 / 3.0 {
                    // Tube center circle at 0.7 r, tube 0.3 r: within the ball of radius r.
                    Shape::Torus(Box::new(Torus::new(center, axis, 0.7 * r, 0.3 * r)))
                } else {
                    // Height 1.2 r, base radius 0.8 r, centerd: within the ball of radius r.
                    Shape::Cone(Box::new(Cone::new(center - axis * (0.6 * r), axis, 1.2 * r, 0.8 * r)))
                }
            }
            _ => Shape::Sphere(Sphere::new(center, r)),
        };
        (self.z_order(center), shape, material)
    }

    /// One triangle: center, radius and material as every object, then the normal of its
    /// plane and its turn in that plane; its corners and the Z-order code of its center.
    fn draw_triangle(&self, s: &mut Stream) -> (u64, [DVec3; 3], usize) {
        let mut u = || s.next_f64();
        let (center, r, material) = self.place(&mut u);
        let frame = crate::math::Frame::from_z(direction(&mut u));
        let turn = std::f64::consts::TAU * u();
        let corner = |k: f64| {
            let a = turn + k * (std::f64::consts::TAU / 3.0);
            center + frame.to_world(DVec3::new(libm::cos(a), libm::sin(a), 0.0)) * r
        };
        (self.z_order(center), [corner(0.0), corner(1.0), corner(2.0)], material)
    }
}

/// Reorders `items` so that `items[j]` becomes the item that was at `order[j]`, in place:
/// each cycle of the permutation is followed once, by swaps.
fn gather_in_place<T>(items: &mut [T], order: &[u32]) {
    let mut placed = vec![false; items.len()];
    for start in 0..items.len() {
        let mut j = start;
        while !placed[j] {
            placed[j] = true;
            let from = order[j] as usize;
            if from == start {
                break;
            }
            items.swap(j, from);
            j = from;
        }
    }
}

/// A uniform direction: `z` uniform in [-1, 1], the azimuth uniform.
fn direction(u: &mut dyn FnMut() -> f64) -> DVec3 {
    let z = 2.0 * u() - 1.0;
    let phi = std::f64::consts::TAU * u();
    let rho = other_leg(z);
    DVec3::new(rho * libm::cos(phi), rho * libm::sin(phi), z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gather_in_place_takes_each_item_from_its_place_in_the_order() {
        let mut items = ['a', 'b', 'c', 'd', 'e', 'f'];
        // Cycles (0 2 4 3 1) and (5).
        gather_in_place(&mut items, &[2, 0, 4, 1, 3, 5]);
        assert_eq!(items, ['c', 'a', 'e', 'b', 'd', 'f']);
        let mut identity = [1, 2, 3];
        gather_in_place(&mut identity, &[0, 1, 2]);
        assert_eq!(identity, [1, 2, 3]);
    }

    fn table(kind: GenerateKind, count: usize) -> Generate {
        Generate {
            kind,
            count,
            seed: 7,
            min: DVec3::new(-1.0, -2.0, 0.0),
            max: DVec3::new(1.0, 2.0, 3.0),
            radius: (0.01, 0.1),
            materials: vec![0, 2],
        }
    }

    #[test]
    fn objects_stay_in_the_region_and_are_reproducible() {
        for kind in [GenerateKind::Spheres, GenerateKind::Mixed, GenerateKind::Triangles] {
            let g = table(kind, CHUNK + 10);
            let a = g.objects(0);
            assert_eq!(a.len(), CHUNK + 10);
            assert_eq!(a, g.objects(0));
            assert_ne!(a, g.objects(1), "another table draws other objects");
            for o in &a {
                let b = o.shape.bounds().unwrap();
                assert!(
                    b.min.cmpge(g.min - 0.1001).all() && b.max.cmple(g.max + 0.1001).all(),
                    "{o:?}"
                );
                assert!(o.material == 0 || o.material == 2);
            }
        }
        let kinds: Vec<&str> = table(GenerateKind::Mixed, 300)
            .objects(0)
            .iter()
            .map(|o| o.shape.kind())
            .collect();
        for k in ["sphere", "torus", "cone"] {
            let n = kinds.iter().filter(|&&x| x == k).count();
            assert!((70..130).contains(&n), "{k}: {n} of 300");
        }
    }

    #[test]
    fn triangles_are_equilateral_and_share_one_vertex_array() {
        let objects = table(GenerateKind::Triangles, 500).objects(3);
        let Shape::Triangle(first) = &objects[0].shape else {
            panic!("{:?}", objects[0]);
        };
        for (i, o) in objects.iter().enumerate() {
            let Shape::Triangle(t) = &o.shape else {
                panic!("{o:?}");
            };
            // Object i holds vertices 3i .. 3i + 2 of the table's one array.
            let (shared, index) = t.shared();
            assert!(Arc::ptr_eq(shared, first.shared().0));
            assert_eq!(index, [3 * i as u32, 3 * i as u32 + 1, 3 * i as u32 + 2]);
            // Sides r sqrt(3) for a radius r in [0.01, 0.1].
            let [a, b, c] = t.points();
            let sides = [(b - a).length(), (c - b).length(), (a - c).length()];
            assert!(
                sides.iter().all(|s| (s - sides[0]).abs() < 1e-12 * sides[0]),
                "{sides:?}"
            );
            let r = sides[0] / 3f64.sqrt();
            assert!((0.01 - 1e-12..=0.1 + 1e-12).contains(&r), "{r}");
        }
    }
}
