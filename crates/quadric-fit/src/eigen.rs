//! Eigen-decomposition of small symmetric matrices (cyclic Jacobi), without `std`.
//!
//! Used for the 10 × 10 scatter matrix of the least-squares quadric fit (eq. 2) and the
//! 3 × 3 covariance of the plane fallback. Jacobi rotations are slow for large matrices
//! but unconditionally stable and accurate to a few ulps of the matrix norm, which is what
//! a fit of nearly degenerate point sets needs.

/// Eigenvalues (ascending) and the matching unit eigenvectors (`vectors[k]` belongs to
/// `values[k]`) of the symmetric matrix `matrix` (only its upper triangle is read).
///
/// Returns `None` when the matrix holds a non-finite value.
pub fn symmetric_eigen<const N: usize>(matrix: &[[f64; N]; N]) -> Option<([f64; N], [[f64; N]; N])> {
    let mut a = [[0.0; N]; N];
    for i in 0..N {
        for j in i..N {
            if !matrix[i][j].is_finite() {
                return None;
            }
            a[i][j] = matrix[i][j];
            a[j][i] = matrix[i][j];
        }
    }
    // v[i][k]: component i of eigenvector k.
    let mut v = [[0.0; N]; N];
    for (i, row) in v.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    let norm: f64 = a.iter().flatten().map(|x| x * x).sum::<f64>();
    for _sweep in 0..64 {
        let off: f64 = (0..N)
            .flat_map(|i| (0..N).filter(move |&j| j != i).map(move |j| (i, j)))
            .map(|(i, j)| a[i][j] * a[i][j])
            .sum();
        if off <= norm * 1e-30 || off == 0.0 {
            break;
        }
        for p in 0..N {
            for q in p + 1..N {
                if a[p][q] == 0.0 {
                    continue;
                }
                // Rotation that zeroes a[p][q] (Golub & Van Loan, Algorithm 8.4.1).
                let tau = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
                let t = if tau >= 0.0 {
                    1.0 / (tau + libm::sqrt(1.0 + tau * tau))
                } else {
                    -1.0 / (-tau + libm::sqrt(1.0 + tau * tau))
                };
                let c = 1.0 / libm::sqrt(1.0 + t * t);
                let s = t * c;
                for row in a.iter_mut() {
                    let (akp, akq) = (row[p], row[q]);
                    row[p] = c * akp - s * akq;
                    row[q] = s * akp + c * akq;
                }
                let (row_p, row_q) = (a[p], a[q]);
                for (k, (&apk, &aqk)) in row_p.iter().zip(&row_q).enumerate() {
                    a[p][k] = c * apk - s * aqk;
                    a[q][k] = s * apk + c * aqk;
                }
                for row in v.iter_mut() {
                    let (vp, vq) = (row[p], row[q]);
                    row[p] = c * vp - s * vq;
                    row[q] = s * vp + c * vq;
                }
            }
        }
    }
    let mut order = [0_usize; N];
    for (i, o) in order.iter_mut().enumerate() {
        *o = i;
    }
    order.sort_unstable_by(|&x, &y| a[x][x].total_cmp(&a[y][y]));
    let mut values = [0.0; N];
    let mut vectors = [[0.0; N]; N];
    for (k, &index) in order.iter().enumerate() {
        values[k] = a[index][index];
        for i in 0..N {
            vectors[k][i] = v[i][index];
        }
    }
    Some((values, vectors))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decomposes_a_known_matrix() {
        // Eigenvalues 1, 2, 4 of a rotated diagonal matrix.
        let m = [[2.0, 0.0, 0.0], [0.0, 2.5, 1.5], [0.0, 1.5, 2.5]];
        let (values, vectors) = symmetric_eigen(&m).unwrap();
        for (value, expected) in values.iter().zip([1.0, 2.0, 4.0]) {
            assert!((value - expected).abs() < 1e-12, "{values:?}");
        }
        for (k, vector) in vectors.iter().enumerate() {
            for i in 0..3 {
                let mv: f64 = (0..3).map(|j| m[i][j] * vector[j]).sum();
                assert!((mv - values[k] * vector[i]).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn rejects_non_finite_input() {
        assert!(symmetric_eigen(&[[f64::NAN, 0.0], [0.0, 1.0]]).is_none());
    }
}
