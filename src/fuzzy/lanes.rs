//! The per-sample loops of the centroid under maximum aggregation (see
//! [`super::inference`]): implied terms folded with `max`, and the area and moment sums
//! `(Σ yᵢ, Σ yᵢ·xᵢ)`.
//!
//! Sums run in [`LANES`] independent partial sums: lane `j` adds the samples `4k + j` of the
//! slice in order, then the lanes are added pairwise, then the samples past the last full group
//! of four, one by one. On x86-64 processors with AVX2 (`AVX2 = true`, chosen at run time by
//! the callers) the lanes are one 256-bit register: the same additions and multiplications in
//! the same order (no fused multiply-add), so the same bits, four samples per instruction.
//! The portable loops give the same results everywhere else.

/// Lanes of the sums: independent partial sums, one vector register of four doubles.
pub(super) const LANES: usize = 4;

/// An implication the loops apply to `(degree, sample)`: the minimum or the algebraic product.
pub(super) trait Implication: Copy {
    /// The algebraic product (else the minimum).
    const PRODUCT: bool;

    /// `min(d, s)` as `if d < s { d } else { s }`, or `d · s`.
    #[inline(always)]
    fn apply(d: f64, s: f64) -> f64 {
        if Self::PRODUCT {
            d * s
        } else if d < s {
            d
        } else {
            s
        }
    }
}

/// Minimum implication.
#[derive(Debug, Clone, Copy)]
pub(super) struct Minimum;

/// Algebraic-product implication.
#[derive(Debug, Clone, Copy)]
pub(super) struct Product;

impl Implication for Minimum {
    const PRODUCT: bool = false;
}

impl Implication for Product {
    const PRODUCT: bool = true;
}

/// `mu[i] = imp(d, row[i])`.
#[inline(always)]
pub(super) fn implied_into<I: Implication>(mu: &mut [f64], row: &[f64], d: f64) {
    for (m, &s) in mu.iter_mut().zip(row) {
        *m = I::apply(d, s);
    }
}

/// `mu[i] = max(mu[i], imp(d, row[i]))`.
#[inline(always)]
pub(super) fn max_into<I: Implication>(mu: &mut [f64], row: &[f64], d: f64) {
    for (m, &s) in mu.iter_mut().zip(row) {
        let v = I::apply(d, s);
        *m = if *m > v { *m } else { v };
    }
}

/// `mu[i] = max(mu[i], imp(d₀, r₀[i]), …, imp(d₃, r₃[i]))`, or without `mu[i]` when `FIRST`.
#[inline(always)]
pub(super) fn max4_into<const FIRST: bool, I: Implication>(mu: &mut [f64], rows: [&[f64]; 4], d: [f64; 4]) {
    let n = mu.len().min(rows[0].len()).min(rows[1].len()).min(rows[2].len()).min(rows[3].len());
    let mu = &mut mu[..n];
    let [r0, r1, r2, r3] = rows.map(|r| &r[..n]);
    for ((((m, &s0), &s1), &s2), &s3) in mu.iter_mut().zip(r0).zip(r1).zip(r2).zip(r3) {
        let y = max4(I::apply(d[0], s0), I::apply(d[1], s1), I::apply(d[2], s2), I::apply(d[3], s3));
        *m = if FIRST || y > *m { y } else { *m };
    }
}

/// `(Σ yᵢ, Σ yᵢ·xᵢ)` with `yᵢ` what [`max4_into`] would write to `mu[i]` (`mu` is only read,
/// and not at all when `FIRST`): the last pass of the dense centroid with its sums.
#[inline(always)]
pub(super) fn max4_sums<const AVX2: bool, const FIRST: bool, I: Implication>(
    mu: &[f64],
    rows: [&[f64]; 4],
    d: [f64; 4],
    xs: &[f64],
) -> (f64, f64) {
    let n = mu.len().min(rows[0].len()).min(rows[1].len()).min(rows[2].len()).min(rows[3].len()).min(xs.len());
    let (mu, xs) = (&mu[..n], &xs[..n]);
    let rows = rows.map(|r| &r[..n]);
    #[cfg(target_arch = "x86_64")]
    if AVX2 {
        // SAFETY: as in `sums`.
        return unsafe { avx2::max4_sums::<FIRST, I>(mu, rows, d, xs) };
    }
    let full = n - n % LANES;
    let mut area = [0.0; LANES];
    let mut moment = [0.0; LANES];
    for k in (0..full).step_by(LANES) {
        for j in 0..LANES {
            let y = max4_at::<FIRST, I>(mu, rows, d, k + j);
            area[j] += y;
            moment[j] += y * xs[k + j];
        }
    }
    max4_sums_tail::<FIRST, I>(fold(area, moment), mu, rows, d, xs, full)
}

/// The samples `from..` of [`max4_sums`] (past the last group of four), added one by one to
/// `(a, s)`.
#[inline(always)]
fn max4_sums_tail<const FIRST: bool, I: Implication>(
    (mut a, mut s): (f64, f64),
    mu: &[f64],
    rows: [&[f64]; 4],
    d: [f64; 4],
    xs: &[f64],
    from: usize,
) -> (f64, f64) {
    for (i, &x) in xs.iter().enumerate().skip(from) {
        let y = max4_at::<FIRST, I>(mu, rows, d, i);
        a += y;
        s += y * x;
    }
    (a, s)
}

/// Sample `i` of [`max4_into`]'s result.
#[inline(always)]
fn max4_at<const FIRST: bool, I: Implication>(mu: &[f64], rows: [&[f64]; 4], d: [f64; 4], i: usize) -> f64 {
    let v = max4(
        I::apply(d[0], rows[0][i]),
        I::apply(d[1], rows[1][i]),
        I::apply(d[2], rows[2][i]),
        I::apply(d[3], rows[3][i]),
    );
    if FIRST || v > mu[i] { v } else { mu[i] }
}

#[inline(always)]
fn max4(a: f64, b: f64, c: f64, d: f64) -> f64 {
    let ab = if a > b { a } else { b };
    let cd = if c > d { c } else { d };
    if ab > cd { ab } else { cd }
}

/// `(Σ yᵢ, Σ yᵢ·xᵢ)`.
#[inline(always)]
pub(super) fn sums<const AVX2: bool>(ys: &[f64], xs: &[f64]) -> (f64, f64) {
    #[cfg(target_arch = "x86_64")]
    if AVX2 {
        // SAFETY: `AVX2` is true only on paths entered after checking that the processor runs
        // AVX2 instructions.
        return unsafe { avx2::sums(ys, xs) };
    }
    lane_sums(ys, xs, |y| y)
}

/// `(Σ yᵢ, Σ yᵢ·xᵢ)` with `yᵢ = imp(d, sᵢ)`.
#[inline(always)]
pub(super) fn implied_sums<const AVX2: bool, I: Implication>(row: &[f64], xs: &[f64], d: f64) -> (f64, f64) {
    #[cfg(target_arch = "x86_64")]
    if AVX2 {
        // SAFETY: as in `sums`.
        return unsafe { avx2::implied_sums::<I>(row, xs, d) };
    }
    lane_sums(row, xs, |s| I::apply(d, s))
}

/// `(Σ yᵢ, Σ yᵢ·xᵢ)` with `yᵢ = max(muᵢ, imp(d, sᵢ))`.
#[inline(always)]
pub(super) fn max_sums<const AVX2: bool, I: Implication>(mu: &[f64], row: &[f64], xs: &[f64], d: f64) -> (f64, f64) {
    #[cfg(target_arch = "x86_64")]
    if AVX2 {
        // SAFETY: as in `sums`.
        return unsafe { avx2::max_sums::<I>(mu, row, xs, d) };
    }
    let n = mu.len().min(row.len()).min(xs.len());
    let (mu, row, xs) = (&mu[..n], &row[..n], &xs[..n]);
    let (mc, mt) = mu.as_chunks::<LANES>();
    let (rc, rt) = row.as_chunks::<LANES>();
    let (xc, xt) = xs.as_chunks::<LANES>();
    let mut area = [0.0; LANES];
    let mut moment = [0.0; LANES];
    for ((m, r), x) in mc.iter().zip(rc).zip(xc) {
        for j in 0..LANES {
            let v = I::apply(d, r[j]);
            let y = if m[j] > v { m[j] } else { v };
            area[j] += y;
            moment[j] += y * x[j];
        }
    }
    let (a, s) = fold(area, moment);
    max_sums_tail::<I>((a, s), mt, rt, xt, d)
}

/// The samples past the last group of four of [`max_sums`], added one by one to `(a, s)`.
#[inline(always)]
fn max_sums_tail<I: Implication>(
    (mut a, mut s): (f64, f64),
    mu: &[f64],
    row: &[f64],
    xs: &[f64],
    d: f64,
) -> (f64, f64) {
    for ((&m, &r), &x) in mu.iter().zip(row).zip(xs) {
        let v = I::apply(d, r);
        let y = if m > v { m } else { v };
        a += y;
        s += y * x;
    }
    (a, s)
}

#[inline(always)]
fn lane_sums(ys: &[f64], xs: &[f64], f: impl Fn(f64) -> f64) -> (f64, f64) {
    let n = ys.len().min(xs.len());
    let (ys, xs) = (&ys[..n], &xs[..n]);
    let (yc, yt) = ys.as_chunks::<LANES>();
    let (xc, xt) = xs.as_chunks::<LANES>();
    let mut area = [0.0; LANES];
    let mut moment = [0.0; LANES];
    for (y, x) in yc.iter().zip(xc) {
        for j in 0..LANES {
            let v = f(y[j]);
            area[j] += v;
            moment[j] += v * x[j];
        }
    }
    lane_sums_tail(fold(area, moment), yt, xt, f)
}

/// The samples past the last group of four of [`lane_sums`], added one by one to `(a, s)`.
#[inline(always)]
fn lane_sums_tail((mut a, mut s): (f64, f64), ys: &[f64], xs: &[f64], f: impl Fn(f64) -> f64) -> (f64, f64) {
    for (&y, &x) in ys.iter().zip(xs) {
        let v = f(y);
        a += v;
        s += v * x;
    }
    (a, s)
}

/// The lanes added pairwise: `((l₀ + l₁) + (l₂ + l₃))` for the area and for the moment.
#[inline(always)]
fn fold(area: [f64; LANES], moment: [f64; LANES]) -> (f64, f64) {
    ((area[0] + area[1]) + (area[2] + area[3]), (moment[0] + moment[1]) + (moment[2] + moment[3]))
}

/// The sums with the four lanes in one AVX2 register.
#[cfg(target_arch = "x86_64")]
mod avx2 {
    use std::arch::x86_64::{
        __m256d, _mm256_add_pd, _mm256_loadu_pd, _mm256_max_pd, _mm256_min_pd, _mm256_mul_pd, _mm256_set1_pd,
        _mm256_setzero_pd, _mm256_storeu_pd,
    };

    use super::{Implication, LANES, fold, lane_sums_tail, max_sums_tail, max4_sums_tail};

    #[inline]
    #[target_feature(enable = "avx2")]
    fn load(v: &[f64; LANES]) -> __m256d {
        // SAFETY: `v` is four readable doubles; the load is unaligned.
        unsafe { _mm256_loadu_pd(v.as_ptr()) }
    }

    #[inline]
    #[target_feature(enable = "avx2")]
    fn lanes(v: __m256d) -> [f64; LANES] {
        let mut out = [0.0; LANES];
        // SAFETY: `out` is four writable doubles; the store is unaligned.
        unsafe { _mm256_storeu_pd(out.as_mut_ptr(), v) };
        out
    }

    /// `imp(d, s)` on four lanes: `_mm256_min_pd(d, s)` is `if d < s { d } else { s }`
    /// lane by lane, NaN included.
    #[inline]
    #[target_feature(enable = "avx2")]
    fn imply<I: Implication>(d: __m256d, s: __m256d) -> __m256d {
        if I::PRODUCT { _mm256_mul_pd(d, s) } else { _mm256_min_pd(d, s) }
    }

    #[inline]
    #[target_feature(enable = "avx2")]
    pub(super) fn sums(ys: &[f64], xs: &[f64]) -> (f64, f64) {
        let n = ys.len().min(xs.len());
        let (ys, xs) = (&ys[..n], &xs[..n]);
        let (yc, yt) = ys.as_chunks::<LANES>();
        let (xc, xt) = xs.as_chunks::<LANES>();
        let mut area = _mm256_setzero_pd();
        let mut moment = _mm256_setzero_pd();
        for (y, x) in yc.iter().zip(xc) {
            let y = load(y);
            area = _mm256_add_pd(area, y);
            moment = _mm256_add_pd(moment, _mm256_mul_pd(y, load(x)));
        }
        lane_sums_tail(fold(lanes(area), lanes(moment)), yt, xt, |y| y)
    }

    #[inline]
    #[target_feature(enable = "avx2")]
    pub(super) fn implied_sums<I: Implication>(row: &[f64], xs: &[f64], d: f64) -> (f64, f64) {
        let n = row.len().min(xs.len());
        let (row, xs) = (&row[..n], &xs[..n]);
        let (rc, rt) = row.as_chunks::<LANES>();
        let (xc, xt) = xs.as_chunks::<LANES>();
        let dv = _mm256_set1_pd(d);
        let mut area = _mm256_setzero_pd();
        let mut moment = _mm256_setzero_pd();
        for (r, x) in rc.iter().zip(xc) {
            let y = imply::<I>(dv, load(r));
            area = _mm256_add_pd(area, y);
            moment = _mm256_add_pd(moment, _mm256_mul_pd(y, load(x)));
        }
        lane_sums_tail(fold(lanes(area), lanes(moment)), rt, xt, |s| I::apply(d, s))
    }

    /// As the portable `max4_sums`: `_mm256_max_pd(a, b)` is `if a > b { a } else { b }`.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub(super) fn max4_sums<const FIRST: bool, I: Implication>(
        mu: &[f64],
        rows: [&[f64]; 4],
        d: [f64; 4],
        xs: &[f64],
    ) -> (f64, f64) {
        let n = mu.len().min(rows[0].len()).min(rows[1].len()).min(rows[2].len()).min(rows[3].len()).min(xs.len());
        let full = n - n % LANES;
        let mc = mu[..full].as_chunks::<LANES>().0;
        let xc = xs[..full].as_chunks::<LANES>().0;
        let [r0, r1, r2, r3] = rows.map(|r| r[..full].as_chunks::<LANES>().0);
        let dv = [_mm256_set1_pd(d[0]), _mm256_set1_pd(d[1]), _mm256_set1_pd(d[2]), _mm256_set1_pd(d[3])];
        let mut area = _mm256_setzero_pd();
        let mut moment = _mm256_setzero_pd();
        for (k, x) in xc.iter().enumerate() {
            let ab = _mm256_max_pd(imply::<I>(dv[0], load(&r0[k])), imply::<I>(dv[1], load(&r1[k])));
            let cd = _mm256_max_pd(imply::<I>(dv[2], load(&r2[k])), imply::<I>(dv[3], load(&r3[k])));
            let v = _mm256_max_pd(ab, cd);
            let y = if FIRST { v } else { _mm256_max_pd(v, load(&mc[k])) };
            area = _mm256_add_pd(area, y);
            moment = _mm256_add_pd(moment, _mm256_mul_pd(y, load(x)));
        }
        max4_sums_tail::<FIRST, I>(fold(lanes(area), lanes(moment)), mu, rows, d, &xs[..n], full)
    }

    /// `_mm256_max_pd(m, v)` is `if m > v { m } else { v }` lane by lane, NaN included.
    #[inline]
    #[target_feature(enable = "avx2")]
    pub(super) fn max_sums<I: Implication>(mu: &[f64], row: &[f64], xs: &[f64], d: f64) -> (f64, f64) {
        let n = mu.len().min(row.len()).min(xs.len());
        let (mu, row, xs) = (&mu[..n], &row[..n], &xs[..n]);
        let (mc, mt) = mu.as_chunks::<LANES>();
        let (rc, rt) = row.as_chunks::<LANES>();
        let (xc, xt) = xs.as_chunks::<LANES>();
        let dv = _mm256_set1_pd(d);
        let mut area = _mm256_setzero_pd();
        let mut moment = _mm256_setzero_pd();
        for ((m, r), x) in mc.iter().zip(rc).zip(xc) {
            let y = _mm256_max_pd(load(m), imply::<I>(dv, load(r)));
            area = _mm256_add_pd(area, y);
            moment = _mm256_add_pd(moment, _mm256_mul_pd(y, load(x)));
        }
        max_sums_tail::<I>(fold(lanes(area), lanes(moment)), mt, rt, xt, d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Samples in `[0, 1]` with zeros, ties and NaN among them, from a fixed sequence.
    fn samples(n: usize, seed: u64) -> Vec<f64> {
        let mut state = seed.wrapping_mul(0x9e37_79b9_7f4a_7c15) | 1;
        (0..n)
            .map(|i| {
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                match i % 11 {
                    0 => 0.0,
                    5 => 0.5,
                    7 if seed.is_multiple_of(3) => f64::NAN,
                    _ => (state >> 11) as f64 / (1u64 << 53) as f64,
                }
            })
            .collect()
    }

    fn same(a: (f64, f64), b: (f64, f64)) -> bool {
        a.0.to_bits() == b.0.to_bits() && a.1.to_bits() == b.1.to_bits()
    }

    #[test]
    fn avx2_sums_equal_the_portable_ones_bit_for_bit() {
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            for n in [0, 1, 3, 4, 5, 8, 13, 100, 1001] {
                for seed in 0..6 {
                    let (mu, row, xs) = (samples(n, seed), samples(n, seed + 7), samples(n, seed + 13));
                    for d in [0.0, 0.25, 0.5, 1.0, f64::NAN] {
                        assert!(same(sums::<true>(&mu, &xs), sums::<false>(&mu, &xs)));
                        let (p, q) =
                            (implied_sums::<true, Minimum>(&row, &xs, d), implied_sums::<false, Minimum>(&row, &xs, d));
                        assert!(same(p, q), "{n} {seed} {d}: {p:?} {q:?}");
                        let (p, q) =
                            (implied_sums::<true, Product>(&row, &xs, d), implied_sums::<false, Product>(&row, &xs, d));
                        assert!(same(p, q), "{n} {seed} {d}: {p:?} {q:?}");
                        let (p, q) = (
                            max_sums::<true, Minimum>(&mu, &row, &xs, d),
                            max_sums::<false, Minimum>(&mu, &row, &xs, d),
                        );
                        assert!(same(p, q), "{n} {seed} {d}: {p:?} {q:?}");
                        let rows = [&row[..], &mu[..], &xs[..], &row[..]];
                        let ds = [d, 0.5, 0.75, 0.125];
                        let mut into = mu.clone();
                        max4_into::<false, Minimum>(&mut into, rows, ds);
                        let want = sums::<false>(&into, &xs);
                        assert!(same(max4_sums::<true, false, Minimum>(&mu, rows, ds, &xs), want));
                        assert!(same(max4_sums::<false, false, Minimum>(&mu, rows, ds, &xs), want));
                        let mut into = mu.clone();
                        max4_into::<true, Product>(&mut into, rows, ds);
                        let want = sums::<false>(&into, &xs);
                        assert!(same(max4_sums::<true, true, Product>(&mu, rows, ds, &xs), want));
                        assert!(same(max4_sums::<false, true, Product>(&mu, rows, ds, &xs), want));
                        let (p, q) = (
                            max_sums::<true, Product>(&mu, &row, &xs, d),
                            max_sums::<false, Product>(&mu, &row, &xs, d),
                        );
                        assert!(same(p, q), "{n} {seed} {d}: {p:?} {q:?}");
                    }
                }
            }
        }
    }
}
