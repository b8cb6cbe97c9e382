//! The one shared tolerance of the crate and the `assert_near!` family of test helpers.
//!
//! Geometry is f64 throughout. `EPS` is the tolerance for "equal up to round-off" in exact-formula
//! tests; tests that need a looser bound state it explicitly next to the assertion.

/// Shared round-off tolerance (absolute, on coordinates of size about 1).
pub const EPS: f64 = 1e-12;

/// Something that has a distance to another value of its own type.
pub trait Near {
    /// Distance between `self` and `other` (absolute value, Euclidean norm for vectors).
    fn dist(&self, other: &Self) -> f64;
}

impl Near for f64 {
    fn dist(&self, other: &Self) -> f64 {
        if self == other {
            0.0
        } else {
            (self - other).abs()
        }
    }
}

impl Near for glam::DVec2 {
    fn dist(&self, other: &Self) -> f64 {
        (*self - *other).length()
    }
}

impl Near for glam::DVec3 {
    fn dist(&self, other: &Self) -> f64 {
        (*self - *other).length()
    }
}

impl<T: Near> Near for [T] {
    fn dist(&self, other: &Self) -> f64 {
        if self.len() != other.len() {
            return f64::INFINITY;
        }
        self.iter()
            .zip(other)
            .map(|(a, b)| a.dist(b))
            .fold(0.0, f64::max)
    }
}

impl<T: Near> Near for Vec<T> {
    fn dist(&self, other: &Self) -> f64 {
        self.as_slice().dist(other.as_slice())
    }
}

/// True when `a` and `b` are within `tol` of each other (NaN is never near anything).
pub fn near<T: Near + ?Sized>(a: &T, b: &T, tol: f64) -> bool {
    let d = a.dist(b);
    d <= tol
}

/// `assert_near!(a, b)` uses [`EPS`]; `assert_near!(a, b, tol)` a given tolerance.
/// Works for `f64`, `DVec2`, `DVec3` and slices/vectors of them.
#[macro_export]
macro_rules! assert_near {
    ($a:expr, $b:expr $(,)?) => {
        $crate::assert_near!($a, $b, $crate::tol::EPS)
    };
    ($a:expr, $b:expr, $tol:expr $(,)?) => {{
        let (a, b, tol) = (&$a, &$b, $tol);
        let d = $crate::tol::Near::dist(a, b);
        assert!(
            d <= tol,
            "assert_near failed: |{} - {}| = {:e} > {:e}\n  left: {:?}\n right: {:?}",
            stringify!($a),
            stringify!($b),
            d,
            tol,
            a,
            b
        );
    }};
    ($a:expr, $b:expr, $tol:expr, $($msg:tt)+) => {{
        let (a, b, tol) = (&$a, &$b, $tol);
        let d = $crate::tol::Near::dist(a, b);
        assert!(
            d <= tol,
            "assert_near failed: |{} - {}| = {:e} > {:e} ({})\n  left: {:?}\n right: {:?}",
            stringify!($a),
            stringify!($b),
            d,
            tol,
            format!($($msg)+),
            a,
            b
        );
    }};
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn near_rejects_nan_and_far_values() {
        assert!(near(&1.0, &(1.0 + 1e-13), EPS));
        assert!(!near(&1.0, &1.1, EPS));
        assert!(!near(&f64::NAN, &f64::NAN, EPS));
        assert!(!near(&vec![1.0, 2.0], &vec![1.0], EPS));
    }

    #[test]
    #[should_panic(expected = "assert_near failed")]
    fn assert_near_panics_when_far() {
        assert_near!(1.0, 2.0);
    }
}
