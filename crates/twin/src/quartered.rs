//! Recordings written straight from each dwell's four quarter means, without a firmware run:
//! for benchmarks and tests whose runs the twin does not make (a million positions, a real
//! gyro's noise, a dwell repeated on purpose). It writes the documented format by itself,
//! like the twin's devices speak the wire, and shares nothing with the parser it feeds.

use std::fmt::Write;

/// A `northfinder-recording/1` text with the quarter-mean columns, built position by position.
#[derive(Debug, Clone)]
pub struct QuarteredRecording {
    text: String,
    positions: usize,
}

impl QuarteredRecording {
    /// The metadata (latitude, dwell, sample rate) and the column header.
    pub fn new(latitude_deg: f64, dwell_s: f64, sample_rate_hz: f64) -> Self {
        let text = format!(
            "# format = northfinder-recording/1\n# latitude_deg = {latitude_deg}\n# dwell_s = {dwell_s}\n\
             # sample_rate_hz = {sample_rate_hz}\nindex,t_s,encoder_deg,rate_dph,q1_dph,q2_dph,q3_dph,q4_dph\n"
        );
        QuarteredRecording { text, positions: 0 }
    }

    /// One position: the dwell's centre time (s), its encoder angle (deg) and its quarter
    /// means (deg/h); the rate column is their mean.
    pub fn position(&mut self, t_s: f64, encoder_deg: f64, quarters: [f64; 4]) {
        let mean = quarters.iter().sum::<f64>() / 4.0;
        let [q1, q2, q3, q4] = quarters;
        let i = self.positions;
        // Writing to a String cannot fail.
        let _ = writeln!(
            self.text,
            "{i},{t_s:.4},{encoder_deg:.7},{mean:.9},{q1:.9},{q2:.9},{q3:.9},{q4:.9}"
        );
        self.positions += 1;
    }

    /// The recording's text.
    pub fn text(&self) -> &str {
        &self.text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rate_is_the_mean_of_the_quarters_and_rows_are_numbered() {
        let mut r = QuarteredRecording::new(43.8, 2.0, 1000.0);
        r.position(1.0, 0.0, [1.0, 2.0, 3.0, 6.0]);
        r.position(3.5, 90.0, [-1.0; 4]);
        let lines: Vec<&str> = r.text().lines().collect();
        assert_eq!(lines[0], "# format = northfinder-recording/1");
        assert!(lines.contains(&"# latitude_deg = 43.8") && lines.contains(&"# dwell_s = 2"));
        assert_eq!(lines[4], "index,t_s,encoder_deg,rate_dph,q1_dph,q2_dph,q3_dph,q4_dph");
        let row: Vec<f64> = lines[5].split(',').map(|c| c.parse().unwrap()).collect();
        assert_eq!(row, [0.0, 1.0, 0.0, 3.0, 1.0, 2.0, 3.0, 6.0]);
        assert!(lines[6].starts_with("1,3.5000,90.0000000,-1.000000000,"));
    }
}
