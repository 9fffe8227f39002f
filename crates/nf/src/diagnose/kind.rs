//! What `nf diagnose` can name: the catalogue of left-out physics, the properties of the gyro's
//! noise, and structure that neither explains.

/// One thing a diagnosis can name. Compared as values, printed by [`Kind::name`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Kind {
    BiasDrift,
    BiasJump,
    ThermalDrift,
    ShaftTilt,
    EncoderError,
    ScaleFactor,
    Nonlinearity,
    SettlingTransient,
    Outliers,
    BiasInstability,
    RateRandomWalk,
    CorrelatedNoise,
    HeavyTails,
    Unexplained,
}

impl Kind {
    /// The deterministic effects a simulation can leave out.
    pub const CATALOGUE: [Kind; 9] = [
        Kind::BiasDrift,
        Kind::BiasJump,
        Kind::ThermalDrift,
        Kind::ShaftTilt,
        Kind::EncoderError,
        Kind::ScaleFactor,
        Kind::Nonlinearity,
        Kind::SettlingTransient,
        Kind::Outliers,
    ];

    /// The identifier in the output and the JSON.
    pub fn name(self) -> &'static str {
        match self {
            Kind::BiasDrift => "bias_drift",
            Kind::BiasJump => "bias_jump",
            Kind::ThermalDrift => "thermal_drift",
            Kind::ShaftTilt => "shaft_tilt",
            Kind::EncoderError => "encoder_error",
            Kind::ScaleFactor => "scale_factor",
            Kind::Nonlinearity => "nonlinearity",
            Kind::SettlingTransient => "settling_transient",
            Kind::Outliers => "outliers",
            Kind::BiasInstability => "bias_instability",
            Kind::RateRandomWalk => "rate_random_walk",
            Kind::CorrelatedNoise => "correlated_noise",
            Kind::HeavyTails => "heavy_tails",
            Kind::Unexplained => "unexplained",
        }
    }

    /// A property of the gyro's noise: measured, used by every test, never a false alarm.
    pub fn is_noise(self) -> bool {
        matches!(
            self,
            Kind::BiasInstability | Kind::RateRandomWalk | Kind::CorrelatedNoise | Kind::HeavyTails
        )
    }
}

impl core::fmt::Display for Kind {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_distinct_and_noise_is_not_catalogue() {
        let mut names: Vec<&str> = Kind::CATALOGUE.iter().map(|k| k.name()).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), Kind::CATALOGUE.len());
        assert!(Kind::CATALOGUE.iter().all(|k| !k.is_noise()));
        assert!(Kind::HeavyTails.is_noise() && !Kind::Unexplained.is_noise());
    }
}
