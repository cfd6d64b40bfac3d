//! Quadrature and root finding used throughout the model.
//!
//! Adaptive Gauss–Kronrod (7–15 point, QUADPACK's QK15 constants) for
//! reference-grade integrals, and fixed Gauss–Legendre panels for hot paths.

use std::sync::OnceLock;

/// Kronrod abscissae (QUADPACK `qk15`), descending, last is the centre.
const XGK: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];
const WGK: [f64; 8] = [
    0.022_935_322_010_529_22,
    0.063_092_092_629_978_55,
    0.104_790_010_322_250_18,
    0.140_653_259_715_525_92,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_727_83,
];
/// Gauss weights for XGK[1], XGK[3], XGK[5] and the centre.
const WG: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

/// One Gauss–Kronrod 7–15 estimate of ∫_a^b f: (Kronrod value, |K − G|).
fn qk15(f: &dyn Fn(f64) -> f64, a: f64, b: f64) -> (f64, f64) {
    let c = 0.5 * (a + b);
    let h = 0.5 * (b - a);
    let fc = f(c);
    let mut k = fc * WGK[7];
    let mut g = fc * WG[3];
    for j in 0..7 {
        let x = h * XGK[j];
        let s = f(c - x) + f(c + x);
        k += WGK[j] * s;
        if j % 2 == 1 {
            g += WG[j / 2] * s;
        }
    }
    (k * h, ((k - g) * h).abs())
}

/// Adaptive ∫_a^b f(x) dx to max(abs_tol, rel_tol·|I|) (QUADPACK QAG
/// strategy: always split the interval with the largest error estimate, at
/// most 2000 intervals, so the cost is bounded even when the tolerance
/// cannot be met).
pub fn integrate(f: &dyn Fn(f64) -> f64, a: f64, b: f64, abs_tol: f64, rel_tol: f64) -> f64 {
    if !(b > a) {
        return 0.0;
    }
    #[derive(PartialEq)]
    struct Piece(f64, f64, f64, f64); // err, a, b, value
    impl Eq for Piece {}
    impl PartialOrd for Piece {
        fn partial_cmp(&self, o: &Self) -> Option<std::cmp::Ordering> {
            Some(self.cmp(o))
        }
    }
    impl Ord for Piece {
        fn cmp(&self, o: &Self) -> std::cmp::Ordering {
            self.0.total_cmp(&o.0)
        }
    }
    let (v, e) = qk15(f, a, b);
    let mut heap = std::collections::BinaryHeap::new();
    heap.push(Piece(e, a, b, v));
    let (mut total, mut err) = (v, e);
    for _ in 0..2000 {
        let tol = abs_tol
            .max(rel_tol * total.abs())
            .max(50.0 * f64::EPSILON * total.abs());
        if err <= tol {
            break;
        }
        let Some(Piece(pe, pa, pb, pv)) = heap.pop() else {
            break;
        };
        let m = 0.5 * (pa + pb);
        if m <= pa || m >= pb {
            heap.push(Piece(0.0, pa, pb, pv));
            continue;
        }
        let (v1, e1) = qk15(f, pa, m);
        let (v2, e2) = qk15(f, m, pb);
        total += v1 + v2 - pv;
        err += e1 + e2 - pe;
        heap.push(Piece(e1, pa, m, v1));
        heap.push(Piece(e2, m, pb, v2));
    }
    // Re-sum to drop the rounding of the running updates.
    heap.iter().map(|p| p.3).sum()
}

/// ∫ over the union of [p_i, p_{i+1}] for sorted break points (kinks).
pub fn integrate_with_breaks(
    f: &dyn Fn(f64) -> f64,
    breaks: &[f64],
    abs_tol: f64,
    rel_tol: f64,
) -> f64 {
    let n = breaks.len().saturating_sub(1).max(1) as f64;
    breaks
        .windows(2)
        .map(|w| integrate(f, w[0], w[1], abs_tol / n, rel_tol))
        .sum()
}

/// ∫_a^∞ f for a function that decays on the length `scale`: panels of
/// doubling width until three in a row add less than the tolerance.
pub fn integrate_to_infinity(
    f: &dyn Fn(f64) -> f64,
    a: f64,
    scale: f64,
    abs_tol: f64,
    rel_tol: f64,
) -> f64 {
    let mut width = scale.max(1e-300);
    let mut lo = a;
    let mut sum = 0.0;
    let mut quiet = 0;
    for _ in 0..200 {
        let part = integrate(f, lo, lo + width, abs_tol, rel_tol);
        sum += part;
        if part.abs() <= abs_tol.max(rel_tol * sum.abs()) {
            quiet += 1;
            if quiet >= 3 {
                break;
            }
        } else {
            quiet = 0;
        }
        lo += width;
        width *= 2.0;
    }
    sum
}

/// Gauss–Legendre nodes and weights on [−1, 1] for `n` points (Newton on
/// the three-term recurrence; accurate to machine precision).
pub fn gauss_legendre(n: usize) -> (Vec<f64>, Vec<f64>) {
    let mut x = vec![0.0; n];
    let mut w = vec![0.0; n];
    let m = n.div_ceil(2);
    for i in 0..m {
        let mut z = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, 0.0);
            for j in 0..n {
                let p2 = p1;
                p1 = p0;
                p0 = ((2 * j + 1) as f64 * z * p1 - j as f64 * p2) / (j + 1) as f64;
            }
            dp = n as f64 * (z * p0 - p1) / (z * z - 1.0);
            let dz = p0 / dp;
            z -= dz;
            if dz.abs() < 1e-16 {
                break;
            }
        }
        x[i] = -z;
        x[n - 1 - i] = z;
        w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
        w[n - 1 - i] = w[i];
    }
    (x, w)
}

/// Cached 8-point Gauss–Legendre rule.
pub fn gl8() -> &'static (Vec<f64>, Vec<f64>) {
    static GL8: OnceLock<(Vec<f64>, Vec<f64>)> = OnceLock::new();
    GL8.get_or_init(|| gauss_legendre(8))
}

/// Fixed composite 8-point Gauss–Legendre over `panels` equal panels of
/// [a, b], integrating a pair of functions at once.
pub fn gauss_legendre_panels(
    a: f64,
    b: f64,
    panels: usize,
    f: impl Fn(f64) -> (f64, f64),
) -> (f64, f64) {
    let (x, w) = gl8();
    let h = (b - a) / panels as f64;
    let mut s = (0.0, 0.0);
    for p in 0..panels {
        let c = a + (p as f64 + 0.5) * h;
        for (xi, wi) in x.iter().zip(w) {
            let v = f(c + 0.5 * h * xi);
            s.0 += wi * v.0;
            s.1 += wi * v.1;
        }
    }
    (0.5 * h * s.0, 0.5 * h * s.1)
}

/// Brent–Dekker minimisation of a unimodal function on [a, b].
pub fn minimize_scalar(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64, tol: f64) -> (f64, f64) {
    const CGOLD: f64 = 0.381_966_011_250_105_1;
    let mut x = a + CGOLD * (b - a);
    let (mut w, mut v) = (x, x);
    let mut fx = f(x);
    let (mut fw, mut fv) = (fx, fx);
    let (mut d, mut e) = (0.0_f64, 0.0_f64);
    for _ in 0..200 {
        let xm = 0.5 * (a + b);
        let tol1 = tol * x.abs() + 1e-12;
        let tol2 = 2.0 * tol1;
        if (x - xm).abs() <= tol2 - 0.5 * (b - a) {
            break;
        }
        let mut golden = true;
        if e.abs() > tol1 {
            let r = (x - w) * (fx - fv);
            let mut q = (x - v) * (fx - fw);
            let mut p = (x - v) * q - (x - w) * r;
            q = 2.0 * (q - r);
            if q > 0.0 {
                p = -p;
            }
            q = q.abs();
            if p.abs() < (0.5 * q * e).abs() && p > q * (a - x) && p < q * (b - x) {
                e = d;
                d = p / q;
                let u = x + d;
                if u - a < tol2 || b - u < tol2 {
                    d = if xm >= x { tol1 } else { -tol1 };
                }
                golden = false;
            }
        }
        if golden {
            e = if x >= xm { a - x } else { b - x };
            d = CGOLD * e;
        }
        let u = if d.abs() >= tol1 {
            x + d
        } else {
            x + tol1.copysign(d)
        };
        let fu = f(u);
        if fu <= fx {
            if u >= x {
                a = x;
            } else {
                b = x;
            }
            (v, fv, w, fw, x, fx) = (w, fw, x, fx, u, fu);
        } else {
            if u < x {
                a = u;
            } else {
                b = u;
            }
            if fu <= fw || w == x {
                (v, fv, w, fw) = (w, fw, u, fu);
            } else if fu <= fv || v == x || v == w {
                (v, fv) = (u, fu);
            }
        }
    }
    (x, fx)
}

/// Nelder–Mead simplex minimisation (used by fits with few parameters).
/// Starts from `x0` with initial steps `step`; returns (x, f(x)).
pub fn nelder_mead(
    f: &dyn Fn(&[f64]) -> f64,
    x0: &[f64],
    step: &[f64],
    max_evals: usize,
    ftol: f64,
) -> (Vec<f64>, f64) {
    let n = x0.len();
    let mut simplex: Vec<Vec<f64>> = vec![x0.to_vec()];
    for i in 0..n {
        let mut p = x0.to_vec();
        p[i] += step[i];
        simplex.push(p);
    }
    let mut values: Vec<f64> = simplex.iter().map(|p| f(p)).collect();
    let mut evals = n + 1;
    while evals < max_evals {
        let mut order: Vec<usize> = (0..=n).collect();
        order.sort_by(|&i, &j| values[i].total_cmp(&values[j]));
        simplex = order.iter().map(|&i| simplex[i].clone()).collect();
        values = order.iter().map(|&i| values[i]).collect();
        if (values[n] - values[0]).abs() <= ftol * (values[0].abs() + 1e-30) {
            break;
        }
        let centroid: Vec<f64> = (0..n)
            .map(|k| simplex[..n].iter().map(|p| p[k]).sum::<f64>() / n as f64)
            .collect();
        let along = |t: f64| -> Vec<f64> {
            (0..n)
                .map(|k| centroid[k] + t * (simplex[n][k] - centroid[k]))
                .collect()
        };
        let xr = along(-1.0);
        let fr = f(&xr);
        evals += 1;
        if fr < values[0] {
            let xe = along(-2.0);
            let fe = f(&xe);
            evals += 1;
            (simplex[n], values[n]) = if fe < fr { (xe, fe) } else { (xr, fr) };
        } else if fr < values[n - 1] {
            (simplex[n], values[n]) = (xr, fr);
        } else {
            let xc = if fr < values[n] {
                along(-0.5)
            } else {
                along(0.5)
            };
            let fc = f(&xc);
            evals += 1;
            if fc < values[n].min(fr) {
                (simplex[n], values[n]) = (xc, fc);
            } else {
                for i in 1..=n {
                    let p: Vec<f64> = (0..n)
                        .map(|k| simplex[0][k] + 0.5 * (simplex[i][k] - simplex[0][k]))
                        .collect();
                    values[i] = f(&p);
                    simplex[i] = p;
                    evals += 1;
                }
            }
        }
    }
    let best = (0..=n)
        .min_by(|&i, &j| values[i].total_cmp(&values[j]))
        .unwrap_or(0);
    (simplex[best].clone(), values[best])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫₀^π sin = 2 (closed form).
    #[test]
    fn adaptive_matches_closed_form() {
        let v = integrate(&|x: f64| x.sin(), 0.0, std::f64::consts::PI, 1e-14, 1e-14);
        assert!((v - 2.0).abs() < 1e-13, "{v}");
    }

    /// ∫₀^∞ e^{−x} = 1 and ∫₀^∞ x² e^{−x} = 2 (Γ(3)).
    #[test]
    fn semi_infinite_matches_gamma_function() {
        let v = integrate_to_infinity(&|x: f64| (-x).exp(), 0.0, 1.0, 1e-14, 1e-14);
        assert!((v - 1.0).abs() < 1e-12, "{v}");
        let v = integrate_to_infinity(&|x: f64| x * x * (-x).exp(), 0.0, 1.0, 1e-14, 1e-14);
        assert!((v - 2.0).abs() < 1e-11, "{v}");
    }

    /// An n-point Gauss–Legendre rule integrates x^(2n−1) exactly.
    #[test]
    fn gauss_legendre_is_exact_for_high_degree() {
        let (x, w) = gauss_legendre(8);
        let s: f64 = x.iter().zip(&w).map(|(x, w)| w * x.powi(14)).sum();
        assert!((s - 2.0 / 15.0).abs() < 1e-14, "{s}");
        assert!((w.iter().sum::<f64>() - 2.0).abs() < 1e-14);
    }

    /// Brent finds the minimum of (x−1.3)² + 2; Nelder–Mead the Rosenbrock valley at (1, 1).
    #[test]
    fn minimisers_find_known_minima() {
        let (x, fx) = minimize_scalar(|x| (x - 1.3) * (x - 1.3) + 2.0, -5.0, 7.0, 1e-10);
        assert!((x - 1.3).abs() < 1e-6 && (fx - 2.0).abs() < 1e-12);
        let rosen = |p: &[f64]| (1.0 - p[0]).powi(2) + 100.0 * (p[1] - p[0] * p[0]).powi(2);
        let (p, _) = nelder_mead(&rosen, &[-1.2, 1.0], &[0.5, 0.5], 5000, 1e-16);
        assert!(
            (p[0] - 1.0).abs() < 1e-4 && (p[1] - 1.0).abs() < 1e-4,
            "{p:?}"
        );
    }
}
