//! The reusable sampling grid of the certified peak: the sin/cos tables of one set of
//! frequencies, and the certification of one amplitude/phase combination on it (grid values,
//! the `bounds` of each interval, refinement of the intervals that can still hold the peak).

use super::bounds::{chord_bound, hermite_bound};
use super::{Peak, PeakOptions, base_frequency, gcd};
use std::f64::consts::TAU;

/// Grid points summed per block (the block of `f` and its table windows stay in L1).
pub(super) const BLOCK: usize = 256;

/// Longest repeat of a tabulated sum of leading terms, points.
const PREFIX_MAX_REPEAT: usize = 2048;

/// The longest run of leading terms (at least 2) whose repeats `p_k` have a least common
/// multiple `P ≤ min(PREFIX_MAX_REPEAT, n/4)`, as `(count, P)`; `(0, 0)` when there is none.
fn leading_repeat(repeat: &[usize], n: usize) -> (usize, usize) {
    let limit = PREFIX_MAX_REPEAT.min(n / 4);
    let mut best = (0, 0);
    let mut p: u128 = 1;
    for (k, &r) in repeat.iter().enumerate() {
        let r = r as u128;
        p = p / gcd(p, r) * r;
        if p > limit as u128 {
            break;
        }
        if k >= 1 {
            best = (k + 1, p as usize);
        }
    }
    best
}

/// A reusable sampling grid for one set of frequencies (sin/cos tables precomputed), so that
/// many phase/amplitude combinations can be evaluated fast (one table pass per evaluation).
///
/// With `ω_k = m_k·ω_g` and `n` points per period, `sin(ω_k t_j) = sin(2π (m_k j mod n)/n)`
/// repeats every `p_k = n / gcd(m_k, n)` points (the paper's 525 rad/s term every 8 of 4 200):
/// each table holds one repeat plus a block, so that any block of the grid reads a contiguous
/// window starting at `j₀ mod p_k`, and the tables stay in cache instead of streaming `8n`
/// values per evaluation. The angles are reduced exactly on integers before the sine.
#[derive(Debug, Clone)]
pub struct PeakGrid {
    pub(super) omegas: Vec<f64>,
    period: f64,
    h: f64,
    n: usize,
    /// `p_k` of every term.
    pub(super) repeat: Vec<usize>,
    pub(super) sin: Vec<Vec<f64>>,
    pub(super) cos: Vec<Vec<f64>>,
    /// The leading terms whose sum repeats within [`PREFIX_MAX_REPEAT`] points (their count, at
    /// least 2, and that repeat, the lcm of their `p_k`), or `(0, 0)`: per evaluation their sum
    /// is tabulated once over one repeat, and the grid pass adds only the other terms to it.
    pub(super) prefix: (usize, usize),
    opts: PeakOptions,
    commensurate: bool,
}

impl PeakGrid {
    /// Precomputes the grid for the frequencies `omegas` (rad/s).
    #[must_use]
    pub fn new(omegas: &[f64], opts: PeakOptions) -> Self {
        let wmax = omegas.iter().copied().fold(0.0, f64::max);
        let base = base_frequency(omegas, opts.max_denominator);
        // A common period needing more than 2·10⁷ grid points, or tables of more than 4·10⁷
        // values per sin/cos set (≈ 320 MB), is treated as none (the frequencies are then
        // incommensurate for any practical window).
        let terms = omegas.len().max(1) as f64;
        let base = base.filter(|g| {
            let n = wmax / g * opts.samples_per_min_period.max(4) as f64;
            n <= 2e7 && n * terms <= 4e7
        });
        let commensurate = base.is_some() || wmax == 0.0;
        let (period, n) = match base {
            Some(g) => {
                let period = TAU / g;
                let tmin = TAU / wmax;
                let n =
                    ((period / tmin) * opts.samples_per_min_period.max(4) as f64).ceil() as usize;
                (period, n.max(8))
            }
            None => (1.0, 1),
        };
        let h = period / n as f64;
        let grid = commensurate && wmax > 0.0;
        // m_k = ω_k/ω_g, an integer to the base's 1e-9 (zero for a constant term).
        let multiples: Vec<u64> = match base {
            Some(g) if grid => omegas.iter().map(|w| (w / g).round() as u64).collect(),
            _ => Vec::new(),
        };
        let nn = n as u64;
        let repeat: Vec<usize> = multiples
            .iter()
            .map(|&m| (nn / gcd(u128::from(m % nn), u128::from(nn)) as u64) as usize)
            .collect();
        let (sin, cos) = multiples
            .iter()
            .zip(&repeat)
            .map(|(&m, &p)| {
                (0..p + BLOCK)
                    .map(|i| {
                        // (m·i mod n)/n of a turn, taken into [−½, ½) before the sine.
                        let a = (m % nn) * (i as u64 % nn) % nn;
                        let a = if 2 * a >= nn {
                            a as f64 - n as f64
                        } else {
                            a as f64
                        };
                        (TAU * a / n as f64).sin_cos()
                    })
                    .unzip::<f64, f64, Vec<f64>, Vec<f64>>()
            })
            .unzip();
        Self {
            omegas: omegas.to_vec(),
            period,
            h,
            n: if grid { n } else { 0 },
            prefix: leading_repeat(&repeat, n),
            repeat,
            sin,
            cos,
            opts,
            commensurate,
        }
    }

    /// `(sin ω_k t_j, cos ω_k t_j)` from the tables.
    fn table(&self, k: usize, j: usize) -> (f64, f64) {
        // n < 2³² (at most 2·10⁷ points): a 32-bit division is several times faster.
        let i = (j as u32 % self.repeat[k] as u32) as usize;
        (self.sin[k][i], self.cos[k][i])
    }

    /// Number of grid points.
    #[must_use]
    pub fn len(&self) -> usize {
        self.n
    }

    /// True when there is no time grid (all frequencies zero or incommensurate).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Local maximum of |f| in `[t_j − h, t_j + h]` from `t_j + s0·h` (the interpolant's maximum,
    /// or the middle): Newton on f′ (f″ from the same sums), falling
    /// back to golden-section search if a step leaves the bracket or f″ has the wrong sign.
    ///
    /// The terms `(sin ω_k t, cos ω_k t)` come from the tables at `t_j`, turned once by
    /// `ω_k (t − t_j)` and then by each Newton step `ω_k δ` — for a step below [`SMALL_TURN`] rad
    /// by its Taylor series, exact to rounding — so a refinement costs one `sin_cos` per term
    /// instead of one per term and iteration.
    fn refine(&self, sig: &Signal, j: usize, s0: f64, tol: f64) -> (f64, f64) {
        let (amps, phases, cs, sn) = (sig.amps, sig.phases, &sig.cs[..], &sig.sn[..]);
        let (lo, hi) = ((j as f64 - 0.5) * self.h, (j as f64 + 1.5) * self.h);
        let mut t = (j as f64 + s0) * self.h;
        let mut terms: Vec<(f64, f64)> = (0..cs.len())
            .map(|k| turn(self.table(k, j), self.omegas[k] * (s0 * self.h)))
            .collect();
        let sums = |terms: &[(f64, f64)]| {
            let (mut f, mut d1, mut d2) = (0.0, 0.0, 0.0);
            for (k, &(s, c)) in terms.iter().enumerate() {
                let w = self.omegas[k];
                f += cs[k] * s + sn[k] * c;
                d1 += w * (cs[k] * c - sn[k] * s);
                d2 -= w * w * (cs[k] * s + sn[k] * c);
            }
            (f, d1, d2)
        };
        for _ in 0..30 {
            let (f, d1, d2) = sums(&terms);
            // A maximum of |f| needs f·f″ < 0.
            if !(f * d2 < 0.0) {
                break;
            }
            let step = d1 / d2;
            let next = t - step;
            if !(next >= lo && next <= hi) {
                break;
            }
            t = next;
            for (k, sc) in terms.iter_mut().enumerate() {
                *sc = turn(*sc, -self.omegas[k] * step);
            }
            if step.abs() <= tol {
                return (t, sums(&terms).0.abs());
            }
        }
        golden_max(|t| self.eval(amps, phases, t).abs(), lo, hi, tol)
    }

    fn eval(&self, amps: &[f64], phases: &[f64], t: f64) -> f64 {
        amps.iter()
            .zip(phases)
            .zip(&self.omegas)
            .map(|((a, p), w)| a * (w * t + p).sin())
            .sum()
    }

    /// Certified `max_t |Σ A_k sin(ω_k t + φ_k)|` for amplitudes and phases matching the grid's
    /// frequencies.
    #[must_use]
    pub fn peak(&self, amps: &[f64], phases: &[f64]) -> Peak {
        thread_local! {
            // The grid values of the last evaluation on this thread: reused, not reallocated
            // and zeroed per evaluation (every value is overwritten by the grid pass).
            static GRID_VALUES: std::cell::RefCell<Vec<f64>> = const { std::cell::RefCell::new(Vec::new()) };
        }
        GRID_VALUES.with_borrow_mut(|f| self.peak_on(amps, phases, f))
    }

    fn peak_on(&self, amps: &[f64], phases: &[f64], f: &mut Vec<f64>) -> Peak {
        let wmax = self.omegas.iter().copied().fold(0.0, f64::max);
        let m2: f64 = amps
            .iter()
            .zip(&self.omegas)
            .map(|(a, w)| a.abs() * w * w)
            .sum();
        if let Some(peak) = self.without_grid(amps, phases, wmax) {
            return peak;
        }
        let n = self.len();
        let sig = Signal::new(amps, phases);
        let h = self.h;
        let loss = m2 * h * h / 8.0;
        f.resize(n, 0.0);
        // Two periodic parts: the same best value and candidates from their few values.
        let (gmax, cand) = match self.split_pass(&sig.cs, &sig.sn, loss, f) {
            Some(pass) => pass,
            None => self.grid_pass(&sig.cs, &sig.sn, loss, f),
        };
        let bounds = self.interval_bounds(&sig, f, cand, gmax, loss);
        let tol = self.opts.tol_relative * TAU / wmax;
        let best = self.best_refined(&sig, f, &bounds, tol);
        Peak {
            value: best.0,
            time_s: best.1,
            period_s: self.period,
            grid_points: n,
            grid_loss_bound: m2 * self.h * self.h / 8.0,
            commensurate: true,
        }
    }

    /// The peak when there is no grid: `|f(0)|` of a constant (`wmax = 0`), or the bound `Σ|A_k|`
    /// of incommensurate frequencies; `None` when the grid applies.
    fn without_grid(&self, amps: &[f64], phases: &[f64], wmax: f64) -> Option<Peak> {
        if wmax == 0.0 {
            let v = self.eval(amps, phases, 0.0).abs();
            return Some(Peak {
                value: v,
                time_s: 0.0,
                period_s: f64::INFINITY,
                grid_points: 1,
                grid_loss_bound: 0.0,
                commensurate: true,
            });
        }
        if !self.commensurate {
            let v = amps.iter().map(|a| a.abs()).sum();
            return Some(Peak {
                value: v,
                time_s: f64::NAN,
                period_s: f64::INFINITY,
                grid_points: 0,
                grid_loss_bound: 0.0,
                commensurate: false,
            });
        }
        None
    }

    /// Upper bounds of |f| on the candidate intervals `cand` (start indices from the grid pass,
    /// best grid value `gmax`, coarse loss `M2·h²/8`), as `(bound, j, s0)` sorted best bound
    /// first, `s0` the start of the refinement in the interval (fraction of `h`).
    ///
    /// Every grid interval has an upper bound of |f| on it: max(|f_j|, |f_j+1|) + M2·h²/8
    /// (coarse), or the maximum of the cubic Hermite interpolant of (f, f′) plus its error bound
    /// M4·h⁴/384 (fine, M4 = Σ|A|ω⁴). Only intervals whose [`chord_bound`] reaches the best grid
    /// value get the fine bound ([`hermite_bound`]); they are refined best bound first until the
    /// best refined value exceeds every remaining bound, so the result is certified.
    fn interval_bounds(
        &self,
        sig: &Signal,
        f: &[f64],
        mut cand: Vec<usize>,
        gmax: f64,
        loss: f64,
    ) -> Vec<(f64, usize, f64)> {
        let (amps, cs, sn) = (sig.amps, &sig.cs, &sig.sn);
        let n = self.len();
        let h = self.h;
        let deriv = |j: usize| -> f64 {
            (0..amps.len())
                .map(|k| {
                    let (s, c) = self.table(k, j);
                    self.omegas[k] * (cs[k] * c - sn[k] * s)
                })
                .sum()
        };
        let m4: f64 = amps
            .iter()
            .zip(&self.omegas)
            .map(|(a, w)| a.abs() * w.powi(4))
            .sum();
        let herm = m4 * h.powi(4) / 384.0;
        // `next(j)` = (j + 1) mod n without an integer division per grid point.
        let next = |j: usize| if j + 1 == n { 0 } else { j + 1 };
        cand.sort_unstable();
        cand.dedup();
        // An interval below the best grid value by the chord bound cannot hold the peak (a
        // relative 1e-12 covers the rounding).
        let c = 4.0 * loss;
        cand.retain(|&j| {
            let b = chord_bound(f[j], f[next(j)], c);
            !(b + 1e-12 * gmax.abs() < gmax)
        });
        // f′ at the candidates' end points, each computed once (neighbouring intervals share one).
        let mut last_deriv: (usize, f64) = (usize::MAX, 0.0);
        let mut deriv_at = |j: usize| {
            if last_deriv.0 != j {
                last_deriv = (j, deriv(j));
            }
            last_deriv.1
        };
        let mut bounds: Vec<(f64, usize, f64)> = cand
            .into_iter()
            .map(|j| {
                let k = next(j);
                let (y0, y1) = (f[j], f[k]);
                if y0 * y1 <= 0.0 {
                    return (y0.abs().max(y1.abs()) + loss, j, 0.5);
                }
                let d0 = deriv_at(j);
                let d1 = deriv_at(k);
                let (mx, at) = hermite_bound((y0, y1), (d0 * h, d1 * h), loss);
                (mx + herm, j, at)
            })
            .collect();
        bounds.sort_by(|a, b| b.0.total_cmp(&a.0));
        bounds
    }

    /// The best `(|f|, t mod period)` over the intervals `bounds` (from
    /// [`PeakGrid::interval_bounds`]), refining at least `refine_top` of them and then every one
    /// whose bound still reaches the best value; `tol` is the refinement tolerance, s.
    fn best_refined(
        &self,
        sig: &Signal,
        f: &[f64],
        bounds: &[(f64, usize, f64)],
        tol: f64,
    ) -> (f64, f64) {
        let n = self.len();
        let h = self.h;
        let next = |j: usize| if j + 1 == n { 0 } else { j + 1 };
        let mut best = (f64::NEG_INFINITY, 0.0);
        for (rank, &(bound, j, s0)) in bounds.iter().enumerate() {
            if rank >= self.opts.refine_top.max(1) && bound < best.0 {
                break;
            }
            // The interval's maximum is at an end point or at a stationary point inside.
            let (t, v) = self.refine(sig, j, s0, tol);
            let ends = f[j].abs().max(f[next(j)].abs());
            let (t, v) = if ends > v {
                (
                    if f[j].abs() >= f[next(j)].abs() {
                        j as f64 * h
                    } else {
                        (j + 1) as f64 * h
                    },
                    ends,
                )
            } else {
                (t, v)
            };
            if v > best.0 {
                best = (v, t.rem_euclid(self.period));
            }
        }
        best
    }
}

/// One amplitude/phase combination evaluated on a grid: `f(t) = Σ A_k sin(ω_k t + φ_k)
/// = Σ cs_k sin ω_k t + sn_k cos ω_k t`.
struct Signal<'a> {
    /// Amplitudes `A_k`.
    amps: &'a [f64],
    /// Phases `φ_k`, rad.
    phases: &'a [f64],
    /// Sine coefficients `A_k cos φ_k`.
    cs: Vec<f64>,
    /// Cosine coefficients `A_k sin φ_k`.
    sn: Vec<f64>,
}

impl<'a> Signal<'a> {
    fn new(amps: &'a [f64], phases: &'a [f64]) -> Self {
        let (cs, sn): (Vec<f64>, Vec<f64>) = amps
            .iter()
            .zip(phases)
            .map(|(a, p)| (a * p.cos(), a * p.sin()))
            .unzip();
        Signal {
            amps,
            phases,
            cs,
            sn,
        }
    }
}

/// Maximises a unimodal `g` on `[a, b]` by golden-section search to `tol`; returns `(t, g(t))`.
/// Largest turn (rad) applied by its Taylor series in [`turn`]: the first omitted terms,
/// `x¹¹/11!` and `x¹⁰/10!`, are below 1e-19 there.
const SMALL_TURN: f64 = 0.05;

/// `(sin(a + x), cos(a + x))` from `(sin a, cos a)`.
fn turn((s, c): (f64, f64), x: f64) -> (f64, f64) {
    let (sx, cx) = if x.abs() <= SMALL_TURN {
        let x2 = x * x;
        (
            x * (1.0 - x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0 * (1.0 - x2 / 72.0)))),
            1.0 - x2 / 2.0 * (1.0 - x2 / 12.0 * (1.0 - x2 / 30.0 * (1.0 - x2 / 56.0))),
        )
    } else {
        x.sin_cos()
    };
    (s * cx + c * sx, c * cx - s * sx)
}

fn golden_max(g: impl Fn(f64) -> f64, mut a: f64, mut b: f64, tol: f64) -> (f64, f64) {
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let mut x1 = b - r * (b - a);
    let mut x2 = a + r * (b - a);
    let (mut g1, mut g2) = (g(x1), g(x2));
    while b - a > tol {
        if g1 < g2 {
            a = x1;
            x1 = x2;
            g1 = g2;
            x2 = a + r * (b - a);
            g2 = g(x2);
        } else {
            b = x2;
            x2 = x1;
            g2 = g1;
            x1 = b - r * (b - a);
            g1 = g(x1);
        }
    }
    let t = 0.5 * (a + b);
    let v = g(t).max(g1).max(g2);
    (t, v)
}
