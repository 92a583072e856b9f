//! The modal assurance criterion, Allemang & Brown (1982):
//! MAC(a, b) = |aᵀb|² / ((aᵀa)(bᵀb)), 1 for parallel shapes, 0 for orthogonal ones.

/// MAC of two real shapes; 0 when either is zero at every test point (a mode the test points
/// do not see shares nothing with any shape), never NaN.
pub fn mac(a: &[f64], b: &[f64]) -> f64 {
    let dot = |x: &[f64], y: &[f64]| x.iter().zip(y).map(|(p, q)| p * q).sum::<f64>();
    let (aa, bb) = (dot(a, a), dot(b, b));
    if aa <= 0.0 || bb <= 0.0 {
        return 0.0;
    }
    let ab = dot(a, b);
    // Rounding can put a parallel pair a few ulps above 1.
    (ab * ab / (aa * bb)).min(1.0)
}

/// MAC of every test shape (rows) with every FE shape (columns).
pub fn mac_matrix(test: &[Vec<f64>], fe: &[Vec<f64>]) -> Vec<Vec<f64>> {
    test.iter()
        .map(|t| fe.iter().map(|f| mac(t, f)).collect())
        .collect()
}
