//! The photon map: photons sorted into cubic cells, and the density estimate (Jensen 2001,
//! section 7.2) that reads back the irradiance they bring to a shading point,
//! `E = sum_p w(d_p) Phi_p / (c pi r^2)`, over the photons within the radius `r` that arrive
//! on the side of the surface the shading normal faces, `w` the filter's weight at distance
//! `d_p` and `c pi r^2` its integral over the disk.
//!
//! The cells are `2 r` wide, so the ball of radius `r` about a point meets at most two cells
//! along each axis; only the occupied cells are kept (hashed), however far apart. Photons are sorted by cell then by their index, and a cell's
//! photons are read in that order: the sum is the same bits however the map was filled.

use crate::scene::PhotonFilter;
use glam::DVec3;
use std::collections::HashMap;
use std::f64::consts::PI;
use std::hash::{BuildHasherDefault, Hasher};

/// A stored photon: where it landed, the direction it arrived along, its flux.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Photon {
    pub position: DVec3,
    /// Unit direction of travel (single precision: only its side of a surface is read).
    pub incoming: [f32; 3],
    /// Flux, in the course's light units (see [`super::emit`]).
    pub flux: [f32; 3],
}

impl Photon {
    pub fn new(position: DVec3, incoming: DVec3, flux: DVec3) -> Self {
        Photon {
            position,
            incoming: incoming.as_vec3().to_array(),
            flux: flux.as_vec3().to_array(),
        }
    }

    pub fn flux(&self) -> DVec3 {
        DVec3::new(self.flux[0] as f64, self.flux[1] as f64, self.flux[2] as f64)
    }

    fn arrives_against(&self, n: DVec3) -> bool {
        let d = self.incoming;
        d[0] as f64 * n.x + d[1] as f64 * n.y + d[2] as f64 * n.z < 0.0
    }
}

impl PhotonFilter {
    /// The weight of a photon at distance `d` from the shading point, with `d^2 = d2 < r^2`.
    fn weight(self, d2: f64, r: f64) -> f64 {
        match self {
            PhotonFilter::Flat => 1.0,
            PhotonFilter::Cone => 1.0 - d2.sqrt() / r,
            PhotonFilter::Epanechnikov => 1.0 - d2 / (r * r),
        }
    }

    /// `c`, the integral of the weight over the disk of radius `r` divided by `pi r^2`:
    /// 1 for the flat filter; `1 - 2 / (3 k)` with `k = 1` for the cone (Jensen 2001,
    /// eq. 7.7): `int_0^r (1 - rho / r) 2 pi rho d rho = pi r^2 / 3`; and
    /// `int_0^r (1 - rho^2 / r^2) 2 pi rho d rho = pi r^2 / 2` for Epanechnikov's.
    pub fn normalisation(self) -> f64 {
        match self {
            PhotonFilter::Flat => 1.0,
            PhotonFilter::Cone => 1.0 / 3.0,
            PhotonFilter::Epanechnikov => 0.5,
        }
    }
}

/// A hasher for cell keys: a rotation, an exclusive or and a multiplication per coordinate
/// (as rustc's FxHash). The table is only looked up, never iterated for a result, so its
/// order never reaches one.
#[derive(Default)]
struct CellHasher(u64);

impl Hasher for CellHasher {
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_u64(u64::from(b));
        }
    }
    fn write_u64(&mut self, x: u64) {
        self.0 = (self.0.rotate_left(5) ^ x).wrapping_mul(0x51_7C_C1_B7_27_22_0A_95);
    }
    fn write_i64(&mut self, x: i64) {
        self.write_u64(x as u64);
    }
    fn finish(&self) -> u64 {
        self.0
    }
}

/// A cell's integer coordinates.
type Cell = (i64, i64, i64);

/// What a density estimate found at a point.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Estimate {
    /// The irradiance `E` the caustic photons bring.
    pub irradiance: DVec3,
    /// The photons inside the radius, on the lit side, that made it.
    pub photons: usize,
}

/// The photons of a caustic pass, sorted by cell.
#[derive(Clone, Debug)]
pub struct PhotonMap {
    photons: Vec<Photon>,
    /// Each occupied cell's range in `photons`.
    cells: HashMap<Cell, (u32, u32), BuildHasherDefault<CellHasher>>,
    /// The least corner of the photons' bounding box, the cells' origin.
    origin: DVec3,
    /// The greatest corner of the photons' bounding box.
    top: DVec3,
    /// Cell side, `2 r`.
    side: f64,
    radius: f64,
    filter: PhotonFilter,
    /// Photons emitted (stored or not).
    emitted: u64,
    /// The most irradiance (largest channel) an estimate can give anywhere.
    irradiance_bound: f64,
}

impl PhotonMap {
    /// The map of `photons` (in index order), read with radius `radius` and `filter`, out of
    /// `emitted` photons sent.
    pub fn build(photons: Vec<Photon>, radius: f64, filter: PhotonFilter, emitted: u64) -> PhotonMap {
        let (origin, top) = photons.iter().fold(
            (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
            |(lo, hi), p| (lo.min(p.position), hi.max(p.position)),
        );
        let side = 2.0 * radius;
        let mut map = PhotonMap {
            photons: Vec::new(),
            cells: HashMap::default(),
            origin,
            top,
            side,
            radius,
            filter,
            emitted,
            irradiance_bound: 0.0,
        };
        let mut keyed: Vec<(Cell, Photon)> = photons.into_iter().map(|p| (map.cell(p.position), p)).collect();
        // Stable: within a cell, photons stay in index order.
        keyed.sort_by_key(|&(k, _)| k);
        let mut start = 0;
        for i in 1..=keyed.len() {
            if i == keyed.len() || keyed[i].0 != keyed[start].0 {
                map.cells.insert(keyed[start].0, (start as u32, i as u32));
                start = i;
            }
        }
        map.photons = keyed.into_iter().map(|(_, p)| p).collect();
        map.irradiance_bound = map.bound();
        map
    }

    /// A bound on every estimate's largest channel: a ball of radius `r` lies within two
    /// cells along each axis, so within the 3 x 3 x 3 cells about any cell it meets; its
    /// photons' weights are at most 1. The largest flux of such a block, over `c pi r^2`,
    /// widened by a relative 1e-9 for rounding.
    fn bound(&self) -> f64 {
        let flux_of = |cell: Cell| {
            self.cells.get(&cell).map_or(DVec3::ZERO, |&(s, e)| {
                self.photons[s as usize..e as usize].iter().map(Photon::flux).sum()
            })
        };
        let mut most: f64 = 0.0;
        for &(x, y, z) in self.cells.keys() {
            let mut block = DVec3::ZERO;
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        block += flux_of((x + dx, y + dy, z + dz));
                    }
                }
            }
            // The largest is the same whatever order the cells are visited in.
            most = most.max(block.max_element());
        }
        most / (self.filter.normalisation() * PI * self.radius * self.radius) * (1.0 + 1e-9)
    }

    /// The most irradiance (largest channel) [`PhotonMap::estimate`] can give anywhere.
    pub fn irradiance_bound(&self) -> f64 {
        self.irradiance_bound
    }

    /// The cell of `p`.
    fn cell(&self, p: DVec3) -> Cell {
        let c = ((p - self.origin) / self.side).floor();
        (c.x as i64, c.y as i64, c.z as i64)
    }

    /// The photons stored, sorted by cell.
    pub fn photons(&self) -> &[Photon] {
        &self.photons
    }

    /// Photons emitted, stored or not.
    pub fn emitted(&self) -> u64 {
        self.emitted
    }

    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// The density estimate at `point` of a surface whose normal, facing the viewer, is
    /// `n`: the photons within the radius that arrive against `n`.
    pub fn estimate(&self, point: DVec3, n: DVec3) -> Estimate {
        let r = self.radius;
        let (lo, hi) = (point - DVec3::splat(r), point + DVec3::splat(r));
        if self.photons.is_empty() || lo.cmpgt(self.top).any() || hi.cmplt(self.origin).any() {
            return Estimate::default();
        }
        let (a, b) = (self.cell(lo), self.cell(hi));
        let r2 = r * r;
        let mut sum = DVec3::ZERO;
        let mut count = 0;
        for x in a.0..=b.0 {
            for y in a.1..=b.1 {
                for z in a.2..=b.2 {
                    let Some(&(s, e)) = self.cells.get(&(x, y, z)) else {
                        continue;
                    };
                    for p in &self.photons[s as usize..e as usize] {
                        let d2 = (p.position - point).length_squared();
                        if d2 < r2 && p.arrives_against(n) {
                            sum += self.filter.weight(d2, r) * p.flux();
                            count += 1;
                        }
                    }
                }
            }
        }
        Estimate {
            irradiance: sum / (self.filter.normalisation() * PI * r2),
            photons: count,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A photon of flux 1 (each channel) arriving straight down at `p`.
    fn down(p: DVec3) -> Photon {
        Photon::new(p, -DVec3::Z, DVec3::ONE)
    }

    #[test]
    fn each_filter_weighs_and_normalises_as_computed_by_hand() {
        let r = 0.2;
        // One photon at distance r / 2 from the shading point, one beyond the radius, one
        // arriving from below (the other side of the surface).
        let photons = vec![
            down(DVec3::new(0.1, 0.0, 0.0)),
            down(DVec3::new(0.0, 0.25, 0.0)),
            Photon::new(DVec3::new(-0.05, 0.0, 0.0), DVec3::Z, DVec3::ONE),
        ];
        let area = PI * r * r;
        // Flat: 1 / (pi r^2). Cone: (1 - 1/2) / (pi r^2 / 3) = 1.5 / (pi r^2). Epanechnikov:
        // (1 - 1/4) / (pi r^2 / 2) = 1.5 / (pi r^2).
        for (filter, expected) in [
            (PhotonFilter::Flat, 1.0 / area),
            (PhotonFilter::Cone, 1.5 / area),
            (PhotonFilter::Epanechnikov, 1.5 / area),
        ] {
            let map = PhotonMap::build(photons.clone(), r, filter, 3);
            let e = map.estimate(DVec3::ZERO, DVec3::Z);
            assert_eq!(e.photons, 1, "{filter:?}");
            assert!(
                (e.irradiance.x - expected).abs() < 1e-12 * expected,
                "{filter:?}: {e:?}"
            );
            // Seen from below, only the photon arriving from below counts: distance r / 4.
            let e = map.estimate(DVec3::ZERO, -DVec3::Z);
            assert_eq!(e.photons, 1);
            let w = match filter {
                PhotonFilter::Flat => 1.0,
                PhotonFilter::Cone => 0.75,
                PhotonFilter::Epanechnikov => 1.0 - 1.0 / 16.0,
            };
            let expected = w / (filter.normalisation() * area);
            assert!((e.irradiance.x - expected).abs() < 1e-12 * expected);
        }
    }

    #[test]
    fn photons_in_neighbouring_cells_are_found_and_far_points_see_none() {
        // A line of photons every 0.05 along x: cells of side 2 r = 0.2 hold four each. The
        // estimate at x counts those strictly within r = 0.1 (no photon at a tie).
        let photons: Vec<Photon> = (0..100).map(|i| down(DVec3::new(i as f64 * 0.05, 0.0, 0.0))).collect();
        let map = PhotonMap::build(photons, 0.1, PhotonFilter::Flat, 100);
        for (x, count) in [
            (2.01, 4),
            (0.02, 3),
            (4.99, 2),
            (5.04, 1),
            (-0.07, 1),
            (5.3, 0),
            (-0.2, 0),
        ] {
            let e = map.estimate(DVec3::new(x, 0.0, 0.0), DVec3::Z);
            assert_eq!(e.photons, count, "at x = {x}");
        }
        // Far outside the photons' box.
        assert_eq!(map.estimate(DVec3::new(0.0, 50.0, 0.0), DVec3::Z), Estimate::default());
    }

    #[test]
    fn the_bound_holds_every_estimate() {
        // A cluster and a sparse line: the bound is at least the largest estimate found on a
        // fine scan, and not absurdly above it (within the 27 cells' worth).
        let mut photons: Vec<Photon> = (0..50).map(|i| down(DVec3::new(0.001 * i as f64, 0.0, 0.0))).collect();
        photons.extend((0..50).map(|i| down(DVec3::new(1.0 + 0.1 * i as f64, 0.0, 0.0))));
        for filter in [PhotonFilter::Flat, PhotonFilter::Cone, PhotonFilter::Epanechnikov] {
            let map = PhotonMap::build(photons.clone(), 0.05, filter, 100);
            let most = (0..2000)
                .map(|i| {
                    map.estimate(DVec3::new(-0.5 + 0.003 * i as f64, 0.0, 0.0), DVec3::Z)
                        .irradiance
                        .x
                })
                .fold(0.0, f64::max);
            let bound = map.irradiance_bound();
            assert!(
                most <= bound && bound <= 27.0 * most,
                "{filter:?}: {most} against {bound}"
            );
        }
    }
}
