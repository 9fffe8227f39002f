//! What a run's fault means, for a person: the host's messages (the main run, `nf simulate`).
//! The MCU logs faults through defmt and never formats them, so none of this is linked there.

use crate::adc::AdcError;
use crate::encoder::EncoderError;
use crate::inclinometer::InclError;
use crate::run::{Fault, RunError, Stage};
use crate::stepper::MotorError;
use core::fmt;

impl fmt::Display for Stage {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Stage::Levelling => f.write_str("while levelling"),
            Stage::Position(k) => write!(f, "at visit {k} (visiting order, from 0)"),
            Stage::Fitting => f.write_str("in the fit"),
        }
    }
}

impl fmt::Display for RunError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}: {}", self.stage, self.fault)
    }
}

impl fmt::Display for Fault {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Fault::BadConfig => f.write_str("the settings cannot make a run (no positions, or no samples in a dwell)"),
            Fault::Order(e) => write!(f, "the visiting order: {e}"),
            Fault::Noise(e) => write!(f, "the noise model: {e}"),
            Fault::Stall {
                commanded_steps,
                moved_counts,
            } => write!(
                f,
                "the motor stalled: {commanded_steps} steps commanded, the encoder moved {moved_counts} counts"
            ),
            Fault::NotReached { error_counts } => write!(
                f,
                "the shaft did not reach its position: {error_counts} encoder counts off after the corrective moves"
            ),
            Fault::Motor(MotorError::Pin) => f.write_str("the motor: a step or direction pin could not be driven"),
            Fault::Motor(MotorError::Stopped) => f.write_str("the motor: the move was stopped"),
            Fault::Encoder(e) => write!(f, "the encoder: {}", encoder(e)),
            Fault::Inclinometer(InclError::Bus) => f.write_str("the inclinometer: its serial line reported an error"),
            Fault::Inclinometer(InclError::Timeout) => f.write_str("the inclinometer sent nothing before the timeout"),
            Fault::Inclinometer(InclError::Garbage { bad_lines }) => write!(
                f,
                "the inclinometer sent no valid line ({bad_lines} failed the checksum or the format)"
            ),
            Fault::AdcSaturated { sample } => write!(
                f,
                "the gyro ADC sat at full scale (sample {sample} of the dwell): the rate, or the gyro's noise, is beyond the converter's range"
            ),
            Fault::AdcTimeout { sample } => write!(
                f,
                "the gyro ADC gave no sample within ten sample periods (sample {sample} of the dwell)"
            ),
            Fault::Adc(AdcError::Bus) => f.write_str("the gyro ADC: the SPI bus or the DRDY pin reported an error"),
            Fault::Adc(AdcError::Readback { register, wrote, read }) => write!(
                f,
                "the gyro ADC: register {register:#04x} reads back {read:#04x}, {wrote:#04x} written (no ADC, or a broken bus)"
            ),
            Fault::Adc(AdcError::DrdyTimeout) => {
                f.write_str("the gyro ADC: DRDY did not go low after the self-calibration")
            }
            Fault::Thermometer => f.write_str("the thermometer reported a fault (out of range or stuck)"),
            Fault::TiltOverLimit { tilt_udeg, limit_udeg } => write!(
                f,
                "the shaft is tilted {} deg, beyond the limit of {} deg: level the instrument",
                Micro(tilt_udeg),
                Micro(limit_udeg)
            ),
            Fault::Aborted => f.write_str("aborted"),
            Fault::Fit(e) => write!(f, "the fit: {e}"),
        }
    }
}

fn encoder(e: EncoderError) -> &'static str {
    match e {
        EncoderError::Bus => "the SPI bus reported an error",
        EncoderError::NotResponding => "no acknowledge or start bit (no encoder, no power, or a broken cable)",
        EncoderError::BadFrame => "a frame without its CDS bit, or cut short",
        EncoderError::Crc => "every retry had a CRC error",
        EncoderError::DeviceError => "it flagged an error (dirty disc, over-speed or an internal fault)",
    }
}

/// Micro-degrees as degrees, to the micro-degree.
struct Micro(u32);

impl fmt::Display for Micro {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}.{:06}", self.0 / 1_000_000, self.0 % 1_000_000)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::string::ToString;

    #[test]
    fn a_fault_says_what_and_where() {
        let e = RunError {
            stage: Stage::Position(3),
            fault: Fault::AdcSaturated { sample: 17 },
        };
        assert_eq!(
            e.to_string(),
            "at visit 3 (visiting order, from 0): the gyro ADC sat at full scale (sample 17 of the dwell): the rate, or the gyro's noise, is beyond the converter's range"
        );
        let tilt = Fault::TiltOverLimit {
            tilt_udeg: 1_250_004,
            limit_udeg: 500_000,
        };
        assert_eq!(
            tilt.to_string(),
            "the shaft is tilted 1.250004 deg, beyond the limit of 0.500000 deg: level the instrument"
        );
        let readback = Fault::Adc(AdcError::Readback {
            register: 3,
            wrote: 0xf0,
            read: 0xff,
        });
        assert_eq!(
            readback.to_string(),
            "the gyro ADC: register 0x03 reads back 0xff, 0xf0 written (no ADC, or a broken bus)"
        );
    }
}
