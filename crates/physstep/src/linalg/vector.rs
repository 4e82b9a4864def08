//! The vector updates methods are made of (`axpy`, `axpy_to`, the fused kick and drift of
//! particles) and the scratch buffers they write into. Long arrays are updated in parallel
//! chunks; every element is computed by the same expression whichever thread runs it, so the
//! result is bitwise the same for any thread count.

/// `y += s * x`, elementwise: the one update every method is made of (in parallel for long
/// arrays, bitwise the same for any thread count).
#[inline]
pub fn axpy(y: &mut [f64], s: f64, x: &[f64]) {
    if y.len() >= PAR_MIN {
        use rayon::prelude::*;
        y.par_chunks_mut(PAR_CHUNK).zip(x.par_chunks(PAR_CHUNK)).for_each(|(y, x)| axpy_serial(y, s, x));
    } else {
        axpy_serial(y, s, x);
    }
}

#[inline]
fn axpy_serial(y: &mut [f64], s: f64, x: &[f64]) {
    for (yi, xi) in y.iter_mut().zip(x) {
        *yi += s * xi;
    }
}

/// Arrays at least this long are updated in parallel, in chunks of [`PAR_CHUNK`]. Every
/// element is computed by the same expression whichever thread runs it, so the result is
/// bitwise the same for any thread count.
pub(crate) const PAR_MIN: usize = 1 << 16;
/// Elements per parallel task (256 KiB of f64).
pub(crate) const PAR_CHUNK: usize = 1 << 15;

/// `out = y + s * x` (in parallel for long arrays, like [`axpy`]).
#[inline]
pub fn axpy_to(out: &mut [f64], y: &[f64], s: f64, x: &[f64]) {
    if out.len() >= PAR_MIN {
        use rayon::prelude::*;
        out.par_chunks_mut(PAR_CHUNK)
            .zip(y.par_chunks(PAR_CHUNK))
            .zip(x.par_chunks(PAR_CHUNK))
            .for_each(|((o, y), x)| axpy_to_serial(o, y, s, x));
    } else {
        axpy_to_serial(out, y, s, x);
    }
}

#[inline]
fn axpy_to_serial(out: &mut [f64], y: &[f64], s: f64, x: &[f64]) {
    for ((oi, yi), xi) in out.iter_mut().zip(y).zip(x) {
        *oi = yi + s * xi;
    }
}

/// Kick then drift in one pass, the whole of a velocity-first symplectic Euler update of
/// particles: `v += h a; x += h v; dx = v` (the last keeps `f = [v; a]` without another
/// pass). The same operations per element as a kick then a drift, so bitwise the same
/// result.
#[inline]
pub(crate) fn kick_drift(x: &mut [f64], v: &mut [f64], dx: &mut [f64], a: &[f64], h: f64) {
    if x.len() >= PAR_MIN {
        use rayon::prelude::*;
        x.par_chunks_mut(PAR_CHUNK)
            .zip(v.par_chunks_mut(PAR_CHUNK))
            .zip(dx.par_chunks_mut(PAR_CHUNK))
            .zip(a.par_chunks(PAR_CHUNK))
            .for_each(|(((x, v), dx), a)| kick_drift_serial(x, v, dx, a, h));
    } else {
        kick_drift_serial(x, v, dx, a, h);
    }
}

#[inline]
fn kick_drift_serial(x: &mut [f64], v: &mut [f64], dx: &mut [f64], a: &[f64], h: f64) {
    for (((xi, vi), di), ai) in x.iter_mut().zip(v.iter_mut()).zip(dx.iter_mut()).zip(a) {
        *vi += h * ai;
        *xi += h * *vi;
        *di = *vi;
    }
}

/// A scratch buffer of length `n`, reallocated only when the length changes.
#[inline]
pub fn scratch(buf: &mut Vec<f64>, n: usize) -> &mut [f64] {
    if buf.len() != n {
        buf.clear();
        buf.resize(n, 0.0);
    }
    buf.as_mut_slice()
}
