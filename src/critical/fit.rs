//! Input: the critical levels of a mesh and a layer height `H`. Output:
//! layer plans that honour the flats, and what a uniform plan does to them.
//!
//! - [`fit_layers`]: contiguous layers from the lowest to the highest
//!   critical height (the surface's `z_min` and `z_max`), every up- and
//!   down-facing flat (a height holding a face region) exactly on a layer
//!   boundary, each layer between `H/2` and `3H/2` thick. Between two
//!   consecutive required boundaries `a < b` the gap `D = b - a` is cut
//!   into `n` equal layers, `n >= 1` the count that makes `D / n` closest
//!   to `H` (ties: the thinner layers). Such an `n` always gives
//!   `H/2 <= D/n <= 3H/2` when `D >= H/2`; a gap below `H/2` cannot be
//!   filled and is refused by name ([`FitError::FlatsTooClose`]).
//! - [`audit_uniform`]: for the uniform plan of `wmslice slice
//!   --layer-height H` (planes `Z0 + kH`, each printing the layer
//!   `[p - H/2, p + H/2]` around it from the material just below it, the
//!   CLI's default `--side below`), the layer that prints each flat and
//!   how far from the flat its printed surface is.
//! - [`clusters`]: runs of critical heights closer than `H` to the next,
//!   where a nearly flat surface in several steps prints as stray partial
//!   layers.
//!
//! Everything is exact rational arithmetic; nothing is rounded.

use super::{CriticalLevel, CriticalReport};
use crate::classify::Facing;
use crate::exact::rational::{rat_to_f64, rat_to_string, Rat};
use crate::layers::plan::MAX_LEVELS;
use crate::mesh::validate::Shown;
use num_traits::{Signed, ToPrimitive, Zero};

/// Why a plan cannot be made.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum FitError {
    /// The layer height is zero or negative.
    #[error("layer height must be positive, got {0}")]
    NonPositiveHeight(String),
    /// Two required boundaries (flats, or a flat and the bottom or top)
    /// are closer than `H/2`: no layer between them can be thick enough.
    /// Flats a file's rounding split (an `f32` part's bottom at `0`,
    /// `1.8e-15` and `2.7e-15`) are merged by snapping the mesh.
    #[error("flats at z = {lower} and z = {upper} are {distance} apart (~{approx}), closer than half the layer height {height}, the thinnest layer a plan holds (choose a layer height of at most twice their distance or, when they differ only by a file's rounding, snap the mesh: --snap Q)")]
    FlatsTooClose {
        /// The lower height, `p/q`.
        lower: String,
        /// The upper height, `p/q`.
        upper: String,
        /// Their distance, `p/q` (exact).
        distance: String,
        /// Their distance's nearest double, as text (for reading only).
        approx: String,
        /// The layer height, `p/q`.
        height: String,
    },
    /// Too many layers.
    #[error("the plan has {0} layers, more than the limit of {MAX_LEVELS}")]
    TooMany(String),
    /// No critical height: nothing to plan.
    #[error("the mesh has no critical height")]
    Empty,
}

/// A layer `[bottom, top]`, exact.
pub type Layer = [Rat; 2];

fn check_height(h: &Rat) -> Result<(), FitError> {
    if h.is_positive() {
        Ok(())
    } else {
        Err(FitError::NonPositiveHeight(rat_to_string(h)))
    }
}

/// Whether a level holds a flat (a face region, up or down).
pub fn is_flat(l: &CriticalLevel) -> bool {
    l.faces_up + l.faces_down > 0
}

/// The number of equal layers for a gap `d >= h/2`: the `n >= 1` with
/// `d / n` closest to `h`, ties to the larger `n`.
fn layer_count(d: &Rat, h: &Rat) -> Rat {
    let one = Rat::from_integer(1.into());
    let n0 = (d / h).floor();
    if n0.is_zero() {
        return one;
    }
    let n1 = &n0 + &one;
    let over = d / &n0 - h; // >= 0
    let under = h - d / &n1; // > 0
    if under <= over {
        n1
    } else {
        n0
    }
}

/// Contiguous layers from the lowest to the highest critical height with
/// every flat on a boundary (see the module documentation).
///
/// ```
/// use wmslice::{critical, datasets, exact::parse_rational, Slicer};
/// // Flats at z = 0, 1, 3, 7/2 and 4.
/// let mesh = datasets::by_name("peg_cube").unwrap().build();
/// let report = critical::analyze(&Slicer::new(&mesh).unwrap()).unwrap();
/// let h = parse_rational("0.3").unwrap();
/// let layers = critical::fit::fit_layers(&report, &h).unwrap();
/// let r = |s: &str| parse_rational(s).unwrap();
/// assert_eq!(layers[0], [r("0"), r("1/3")]);
/// for l in &layers {
///     assert!(&l[1] - &l[0] >= &h / r("2") && &l[1] - &l[0] <= &h * r("3/2"));
/// }
/// for z in ["1", "3", "7/2", "4"] {
///     assert!(layers.iter().any(|l| l[1] == r(z)));
/// }
/// ```
pub fn fit_layers(report: &CriticalReport, h: &Rat) -> Result<Vec<Layer>, FitError> {
    check_height(h)?;
    let levels = &report.levels;
    let (Some(first), Some(last)) = (levels.first(), levels.last()) else {
        return Err(FitError::Empty);
    };
    let mut required: Vec<&Rat> = vec![&first.z];
    required.extend(levels.iter().filter(|l| is_flat(l)).map(|l| &l.z));
    required.push(&last.z);
    required.dedup();
    let two = Rat::from_integer(2.into());
    let half = h / &two;
    let mut counts = Vec::with_capacity(required.len());
    let mut total = Rat::zero();
    for w in required.windows(2) {
        let d = w[1] - w[0];
        if d < half {
            return Err(FitError::FlatsTooClose {
                lower: rat_to_string(w[0]),
                upper: rat_to_string(w[1]),
                distance: rat_to_string(&d),
                approx: Shown(rat_to_f64(&d)).to_string(),
                height: rat_to_string(h),
            });
        }
        let n = layer_count(&d, h);
        total += &n;
        counts.push(n);
    }
    let total_n = total
        .to_integer()
        .to_usize()
        .filter(|&n| n <= MAX_LEVELS)
        .ok_or_else(|| FitError::TooMany(rat_to_string(&total)))?;
    let mut layers = Vec::with_capacity(total_n);
    for (w, n) in required.windows(2).zip(&counts) {
        let step = (w[1] - w[0]) / n;
        let n = n.to_integer().to_usize().unwrap_or(0);
        for i in 0..n {
            let bottom = if i == 0 {
                w[0].clone()
            } else {
                w[0] + &step * Rat::from_integer(i.into())
            };
            let top = if i + 1 == n {
                w[1].clone()
            } else {
                w[0] + &step * Rat::from_integer((i + 1).into())
            };
            layers.push([bottom, top]);
        }
    }
    Ok(layers)
}

/// The middle of each layer, where a slicer cuts it (as the uniform plan
/// of `wmslice slice --layer-height` cuts at mid-layer). Exact.
pub fn mid_planes(layers: &[Layer]) -> Vec<Rat> {
    let two = Rat::from_integer(2.into());
    layers.iter().map(|l| (&l[0] + &l[1]) / &two).collect()
}

/// A run of critical heights, each closer than `H` to the next: indices
/// into [`CriticalReport::levels`], ascending, at least two.
pub fn clusters(report: &CriticalReport, h: &Rat) -> Result<Vec<Vec<usize>>, FitError> {
    check_height(h)?;
    let mut out = Vec::new();
    let mut run: Vec<usize> = Vec::new();
    for (i, l) in report.levels.iter().enumerate() {
        match run.last() {
            Some(&p) if &l.z - &report.levels[p].z < *h => run.push(i),
            _ => {
                if run.len() >= 2 {
                    out.push(std::mem::take(&mut run));
                }
                run = vec![i];
            }
        }
    }
    if run.len() >= 2 {
        out.push(run);
    }
    Ok(out)
}

/// What the uniform plan does to one flat.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FlatAudit {
    /// Index of the flat's height in [`CriticalReport::levels`].
    pub level: usize,
    /// `Up` (a top surface: material below) or `Down` (a bottom surface).
    pub facing: Facing,
    /// Face regions of that facing at that height.
    pub regions: usize,
    /// The layer that prints the flat's surface: `k` for the plane
    /// `Z0 + kH` (negative, or past the plan's last plane, when no plane
    /// of the plan prints the material next to the flat).
    pub layer: i64,
    /// That layer, `[p - H/2, p + H/2]`.
    pub bounds: Layer,
    /// Where the printed surface is: the layer's top for an up flat, its
    /// bottom for a down flat.
    pub printed_at: Rat,
    /// `printed_at - z`: 0 when the plan prints the flat where it is.
    pub offset: Rat,
}

/// Audits the uniform plan with planes `first + kH`: for every flat, the
/// layer that prints it and how far off its printed surface is.
///
/// An up flat at `z` has material just below it: the last layer whose
/// plane `p <= z` holds that material (at `p = z` the slice's L- is the
/// flat's rim), so the surface is printed at that layer's top. A down
/// flat has material just above: the first layer with `p > z` prints it,
/// at that layer's bottom.
pub fn audit_uniform(
    report: &CriticalReport,
    h: &Rat,
    first: &Rat,
) -> Result<Vec<FlatAudit>, FitError> {
    check_height(h)?;
    let two = Rat::from_integer(2.into());
    let half = h / &two;
    let one = Rat::from_integer(1.into());
    let mut out = Vec::new();
    for (i, l) in report.levels.iter().enumerate() {
        for (facing, regions) in [(Facing::Down, l.faces_down), (Facing::Up, l.faces_up)] {
            if regions == 0 {
                continue;
            }
            let t = (&l.z - first) / h;
            // Up: k = floor(t) (p_k <= z); down: k = floor(t) + 1 (p_k > z).
            let k = match facing {
                Facing::Up => t.floor(),
                _ => t.floor() + &one,
            };
            let plane = first + h * &k;
            let bounds = [&plane - &half, &plane + &half];
            let printed_at = match facing {
                Facing::Up => bounds[1].clone(),
                _ => bounds[0].clone(),
            };
            let offset = &printed_at - &l.z;
            out.push(FlatAudit {
                level: i,
                facing,
                regions,
                layer: k.to_integer().to_i64().unwrap_or(i64::MAX),
                bounds,
                printed_at,
                offset,
            });
        }
    }
    Ok(out)
}

/// A layer plan to report beside the critical values.
#[derive(Clone, Debug)]
pub enum PlanReport {
    /// `--fit-critical`: the fitted layers.
    Fitted {
        /// The target layer height `H`.
        height: Rat,
        /// The layers, bottom to top.
        layers: Vec<Layer>,
        /// Runs of critical heights closer than `H` (indices into the
        /// report's levels).
        clusters: Vec<Vec<usize>>,
    },
    /// Without `--fit-critical`: what the uniform plan does to each flat.
    Uniform {
        /// The layer height `H`.
        height: Rat,
        /// The first plane `Z0`.
        first: Rat,
        /// One entry per flat and facing.
        audit: Vec<FlatAudit>,
        /// As for [`PlanReport::Fitted`].
        clusters: Vec<Vec<usize>>,
    },
}

impl PlanReport {
    /// The fitted plan of `report` for the layer height `h`
    /// ([`fit_layers`]), with its [`clusters`].
    pub fn fitted(report: &CriticalReport, h: &Rat) -> Result<Self, FitError> {
        Ok(PlanReport::Fitted {
            layers: fit_layers(report, h)?,
            clusters: clusters(report, h)?,
            height: h.clone(),
        })
    }

    /// The audit of the uniform plan `first + k h` ([`audit_uniform`]),
    /// with its [`clusters`].
    pub fn uniform(report: &CriticalReport, h: &Rat, first: &Rat) -> Result<Self, FitError> {
        Ok(PlanReport::Uniform {
            audit: audit_uniform(report, h, first)?,
            clusters: clusters(report, h)?,
            height: h.clone(),
            first: first.clone(),
        })
    }

    /// Its clusters of critical heights closer than `H`.
    pub fn clusters(&self) -> &[Vec<usize>] {
        match self {
            PlanReport::Fitted { clusters, .. } | PlanReport::Uniform { clusters, .. } => clusters,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::exact::parse_rational;

    fn r(s: &str) -> Rat {
        parse_rational(s).unwrap()
    }

    #[test]
    fn layer_count_is_closest_to_h() {
        // D/H = 2.45: 2 layers of 1.225 H or 3 of 0.8167 H: 3 is closer.
        assert_eq!(layer_count(&r("2.45"), &r("1")), r("3"));
        // D/H = 2.4: 1.2 (dev 0.2) vs 0.8 (dev 0.2): tie, the thinner.
        assert_eq!(layer_count(&r("2.4"), &r("1")), r("3"));
        assert_eq!(layer_count(&r("2.3"), &r("1")), r("2"));
        assert_eq!(layer_count(&r("0.5"), &r("1")), r("1"));
        assert_eq!(layer_count(&r("1.6"), &r("1")), r("2"));
    }
}
