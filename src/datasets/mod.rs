//! Input: a dataset name. Output: a deterministic, exactly degenerate
//! [`Mesh`] from the paper's test suite (Mejia-Parra et al. 2020), plus its
//! hand-derived level sets in [`expected`].
//!
//! Every coordinate is an integer or a small dyadic rational (exact in `f64`,
//! |x| < 2^20), so a vertex meant to lie at height `c` has `z == c` exactly.
//! Every mesh is closed, consistently outward-oriented (positive exact
//! signed volume), 2-manifold, without zero-area faces or folds.
//! `DATASETS.md` at the crate root describes each construction and derives
//! the expected level sets at every degenerate height by hand.

mod build;
pub mod cross_check;
pub mod expected;
pub mod families;
mod shapes;
pub mod slab;

use crate::mesh::Mesh;

/// A built-in dataset.
#[derive(Clone, Copy, Debug)]
pub struct Dataset {
    /// snake_case name, as accepted by `wmslice gen NAME` and `slice NAME`.
    pub name: &'static str,
    /// One line: what is degenerate and at which heights.
    pub summary: &'static str,
    /// The exact degenerate heights, as `(numerator, denominator)`.
    pub degenerate_levels: &'static [(i64, u64)],
    build: fn() -> Mesh,
}

impl Dataset {
    /// Builds the mesh (deterministic: equal on every call).
    pub fn build(&self) -> Mesh {
        (self.build)()
    }
}

static ALL: [Dataset; 13] = [
    Dataset {
        name: "unit_cube",
        summary: "flat bottom (down) at z=0 and flat top (up) at z=1",
        degenerate_levels: &[(0, 1), (1, 1)],
        build: shapes::unit_cube,
    },
    Dataset {
        name: "octahedron",
        summary: "minimum at z=-1, square of transversal in-plane edges at z=0, maximum at z=1",
        degenerate_levels: &[(-1, 1), (0, 1), (1, 1)],
        build: shapes::octahedron,
    },
    Dataset {
        name: "pyramid",
        summary: "flat square base (down) at z=0, apex maximum at z=1",
        degenerate_levels: &[(0, 1), (1, 1)],
        build: shapes::pyramid,
    },
    Dataset {
        name: "upright_torus",
        summary: "horizontal-axis torus: min z=-3, regular vertices z=-2,2, ordinary saddles at z=-1 and z=1 (hole bottom/top), two tube sections of in-plane edges at z=0, max z=3",
        degenerate_levels: &[(-3, 1), (-2, 1), (-1, 1), (0, 1), (1, 1), (2, 1), (3, 1)],
        build: shapes::upright_torus,
    },
    Dataset {
        name: "lying_torus",
        summary: "vertical-axis torus: closed valley ring z=-1, inner equator ring (hole) z=0, outer equator ring z=1, closed ridge ring z=2",
        degenerate_levels: &[(-1, 1), (0, 1), (1, 1), (2, 1)],
        build: shapes::lying_torus,
    },
    Dataset {
        name: "double_torus",
        summary: "genus-2 slab: flat bottom z=0, pit and rim vertices z=1, monkey saddle (6 branches) at z=2, two flat top regions and three ridges z=4",
        degenerate_levels: &[(0, 1), (1, 1), (2, 1), (4, 1)],
        build: shapes::double_torus,
    },
    Dataset {
        name: "grid",
        summary: "3x3 pits: flat bottom z=0, nine isolated minima z=1, ridge network (20 open ridges) z=2",
        degenerate_levels: &[(0, 1), (1, 1), (2, 1)],
        build: shapes::grid,
    },
    Dataset {
        name: "cylinder",
        summary: "octagonal prism: flat caps, down at z=0 and up at z=2 (no contour at the caps)",
        degenerate_levels: &[(0, 1), (2, 1)],
        build: shapes::cylinder,
    },
    Dataset {
        name: "internal_torus",
        summary: "box with toroidal cavity: flat bottom z=-2, cavity valley ring z=-1, cavity equator rings z=0 and z=1, cavity ridge ring z=2, flat top z=3",
        degenerate_levels: &[(-2, 1), (-1, 1), (0, 1), (1, 1), (2, 1), (3, 1)],
        build: shapes::internal_torus,
    },
    Dataset {
        name: "peg_cube",
        summary: "cube with two pegs: flat regions down z=0, down z=1, up+down z=3, up z=7/2, up z=4",
        degenerate_levels: &[(0, 1), (1, 1), (3, 1), (7, 2), (4, 1)],
        build: shapes::peg_cube,
    },
    Dataset {
        name: "chamfered_cylinder",
        summary: "octagonal prism with chamfered top: flat bottom z=0, ring of transversal in-plane edges z=2, flat top z=3",
        degenerate_levels: &[(0, 1), (2, 1), (3, 1)],
        build: shapes::chamfered_cylinder,
    },
    Dataset {
        name: "platform_grid",
        summary: "platform with four plateaus: flat bottom z=0, one flat region with four holes z=1, four flat plateaus z=2",
        degenerate_levels: &[(0, 1), (1, 1), (2, 1)],
        build: shapes::platform_grid,
    },
    Dataset {
        name: "saddle8",
        summary: "8-branch saddle (m=4) at z=2; flat bottom z=0, regular corners z=1, four maxima z=3",
        degenerate_levels: &[(0, 1), (1, 1), (2, 1), (3, 1)],
        build: shapes::saddle8,
    },
];

/// Every built-in dataset, in a fixed order.
pub fn all() -> &'static [Dataset] {
    &ALL
}

/// The built-in dataset with this exact name.
pub fn by_name(name: &str) -> Option<&'static Dataset> {
    ALL.iter().find(|d| d.name == name)
}
