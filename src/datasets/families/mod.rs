//! Input: a family name and a seed. Output: a random closed, consistently
//! oriented, non-self-intersecting [`Mesh`] built to hit degeneracies of
//! one kind (flat regions, ridges and valleys, extrema, ordinary and
//! monkey saddles, handles), and with [`answers`] its exact level sets
//! summarised at every critical height and between them.
//!
//! Deterministic: a family and a seed give the same mesh, to the bit, on
//! every machine and thread count. The stream is SplitMix64 ([`rng`]),
//! every coordinate is made by exact integer arithmetic or by the
//! correctly rounded parse of a decimal into an `f32` (the `terraced`
//! family), and vertices are numbered in the order the construction first
//! meets them. Every family is safe by construction (each module's doc
//! says why it is closed and cannot self-intersect); `tests/families.rs`
//! validates many seeds of each.

pub mod answers;
mod egg_crate;
mod grid;
mod handles;
mod height_field;
mod polycube;
pub mod rng;
mod terraced;
mod voxels;

use crate::exact::rational::Rat;
use crate::mesh::Mesh;
use rng::Rng;

/// A family of random meshes.
#[derive(Clone, Copy, Debug)]
pub struct Family {
    /// snake_case name, as `wmslice gen --random SEED --family NAME` takes it.
    pub name: &'static str,
    /// One line: what its meshes exercise.
    pub summary: &'static str,
    /// The snap grid its answers assume, `(p, q)`, when its coordinates are
    /// rounded decimals (`f32` as CAD tools store them).
    snap: Option<(i64, u64)>,
    build: fn(&mut Rng) -> Mesh,
}

impl Family {
    /// The mesh for `seed` (the same bytes on every call and machine).
    pub fn generate(&self, seed: u64) -> Mesh {
        let mut rng = Rng::for_family(self.name, seed);
        (self.build)(&mut rng)
    }

    /// The snap grid the family's answers are computed on (the grid its
    /// decimals were designed on), or `None` when the stored coordinates
    /// are meant exactly.
    pub fn snap(&self) -> Option<Rat> {
        self.snap.map(|(p, q)| Rat::new(p.into(), q.into()))
    }
}

static ALL: [Family; 5] = [
    Family {
        name: "height_field",
        summary: "slabs between integer height fields: plateaus (flat up/down regions), ridge and valley lines, cross saddles; some with through-holes, some turned on their side",
        snap: None,
        build: height_field::build,
    },
    Family {
        name: "polycube",
        summary: "well-composed polycubes on non-uniform grids: closed cavities, notches and tunnels (overhangs), boxes on top; many flat regions with holes per level",
        snap: None,
        build: polycube::build,
    },
    Family {
        name: "terraced",
        summary: "CAD-like terraced parts: flats and pockets at decimal heights (0.2, 2.45, 10.35 mm) stored as f32; answers on the 1/1000 snap grid (--snap 1/1000 matters)",
        snap: Some((1, 1000)),
        build: terraced::build,
    },
    Family {
        name: "egg_crate",
        summary: "egg-crate fields (zero lines of in-plane edges, m=2 saddles where they cross, peaks, pits, flat 2x2 tops) with monkey saddles m=3 and m=4 stamped on",
        snap: None,
        build: egg_crate::build,
    },
    Family {
        name: "handles",
        summary: "rows of tori (lying: ridge/valley rings, flat annuli; upright: saddles at the hole, equators of in-plane edges) and voxel arches, shifted so critical heights coincide",
        snap: None,
        build: handles::build,
    },
];

/// Every family, in a fixed order.
pub fn all() -> &'static [Family] {
    &ALL
}

/// The family with this exact name.
pub fn by_name(name: &str) -> Option<&'static Family> {
    ALL.iter().find(|f| f.name == name)
}
