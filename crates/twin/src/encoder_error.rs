//! A periodic error of the encoder's angle.

/// `amplitude sin(harmonic * angle + phase)`, arcsec, added to the angle the encoder reads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EncoderHarmonic {
    pub harmonic: u8,
    pub amplitude_arcsec: f64,
    pub phase_deg: f64,
}

impl EncoderHarmonic {
    /// No error (harmonic 1 of size 0).
    pub const NONE: EncoderHarmonic = EncoderHarmonic {
        harmonic: 1,
        amplitude_arcsec: 0.0,
        phase_deg: 0.0,
    };

    /// The error at shaft angle `deg`, deg.
    pub fn at_deg(&self, deg: f64) -> f64 {
        self.amplitude_arcsec / 3600.0 * (self.harmonic as f64 * deg + self.phase_deg).to_radians().sin()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_error_peaks_where_the_harmonic_says() {
        let e = EncoderHarmonic {
            harmonic: 2,
            amplitude_arcsec: 36.0,
            phase_deg: 0.0,
        };
        assert!((e.at_deg(45.0) - 0.01).abs() < 1e-15);
        assert!(e.at_deg(90.0).abs() < 1e-15);
        assert_eq!(EncoderHarmonic::NONE.at_deg(33.0), 0.0);
    }
}
