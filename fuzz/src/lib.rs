//! What the fuzz targets share: in-memory fakes of the buses the drivers talk to, fed from the
//! fuzz input, and a printer of host-link commands in the link's own syntax.

pub mod fake;
pub mod link_print;

/// Text of the input: the fuzz input as UTF-8, with invalid sequences replaced.
pub fn text(data: &[u8]) -> std::borrow::Cow<'_, str> {
    String::from_utf8_lossy(data)
}

/// Whether `got` is `want` to within half a unit of the last of `decimals` written digits
/// (plus the rounding of the scaling and of reading the digits back).
pub fn close(got: f64, want: f64, decimals: u32) -> bool {
    let half_unit = 0.5 * 10f64.powi(-(decimals as i32));
    (got - want).abs() <= half_unit * (1.0 + 1e-9) + want.abs() * 4.0 * f64::EPSILON
}
