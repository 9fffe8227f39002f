//! `nf diagnose --evaluate --keep DIR`: the suite's recordings a diagnosis missed, written out
//! with their truth in the metadata, so that each miss can be diagnosed again and read.

use crate::diagnose_eval::Seen;
use std::path::{Path, PathBuf};

/// Writes missed recordings into a directory; the first write that fails stops the writing
/// and is reported at the end.
pub struct Keeper {
    dir: PathBuf,
    pub kept: usize,
    pub failed: Option<String>,
}

impl Keeper {
    /// The directory is made if it is not there.
    pub fn new(dir: &Path) -> Result<Keeper, String> {
        std::fs::create_dir_all(dir).map_err(|e| format!("--keep {}: {e}", dir.display()))?;
        Ok(Keeper {
            dir: dir.to_path_buf(),
            kept: 0,
            failed: None,
        })
    }

    pub fn see(&mut self, s: &Seen<'_>) {
        let Some(missed) = s.missed.filter(|m| m.any()) else {
            return;
        };
        if self.failed.is_some() {
            return;
        }
        let slug: String = s
            .row
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
            .collect();
        let path = self.dir.join(format!("{}-{slug}-{}.csv", s.category, s.number));
        let effects: Vec<&str> = s.truth.effects.iter().map(|k| k.name()).collect();
        let truth = [
            format!("# suite_category = {}", s.category),
            format!("# suite_row = {}", s.row),
            format!("# suite_truth_psi_deg = {:.9}", s.truth.psi_deg),
            format!(
                "# suite_truth_effects = {}",
                if effects.is_empty() {
                    "none".to_string()
                } else {
                    effects.join(" ")
                }
            ),
            format!("# suite_missed = {}", missed.describe()),
        ]
        .join("\n");
        // Metadata goes after the format line, before the header.
        let text = match s.text.split_once('\n') {
            Some((first, rest)) => format!("{first}\n{truth}\n{rest}"),
            None => format!("{truth}\n{}", s.text),
        };
        match std::fs::write(&path, text) {
            Ok(()) => self.kept += 1,
            Err(e) => self.failed = Some(format!("--keep: {}: {e}", path.display())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::diagnose::Kind;
    use crate::diagnose_eval::{Missed, Truth};
    use crate::recording::Recording;

    const TEXT: &str = "# format = northfinder-recording/1\n# latitude_deg = 45\nindex,t_s,encoder_deg,rate_dph\n0,1,0,10.6\n1,2,90,0.1\n2,3,180,-10.6\n3,4,270,0.2\n";

    fn seen<'a>(truth: &'a Truth, missed: Option<Missed>) -> Seen<'a> {
        Seen {
            category: "white",
            row: "bias_jump moderate",
            number: 7,
            text: TEXT,
            truth,
            missed,
        }
    }

    #[test]
    fn a_miss_is_written_with_its_truth_and_reads_as_the_recording_it_was() {
        let dir = std::env::temp_dir().join(format!("nf-keep-{}", std::process::id()));
        let mut k = Keeper::new(&dir).unwrap();
        let truth = Truth {
            effects: vec![Kind::BiasJump],
            psi_deg: 12.5,
        };
        k.see(&seen(&truth, None));
        k.see(&seen(&truth, Some(Missed::default())));
        assert_eq!(k.kept, 0, "a refused or right recording is not kept");
        let missed = Missed {
            worse: true,
            beyond: true,
            ..Missed::default()
        };
        k.see(&seen(&truth, Some(missed)));
        assert_eq!((k.kept, &k.failed), (1, &None));
        let text = std::fs::read_to_string(dir.join("white-bias_jump_moderate-7.csv")).unwrap();
        let rec = Recording::parse(&text).unwrap();
        let original = Recording::parse(TEXT).unwrap();
        assert_eq!(rec.rows.len(), original.rows.len());
        assert!(
            rec.rows
                .iter()
                .zip(&original.rows)
                .all(|(a, b)| a.rate_dph == b.rate_dph)
        );
        assert_eq!(rec.meta["suite_truth_psi_deg"], "12.500000000");
        assert_eq!(rec.meta["suite_truth_effects"], "bias_jump");
        assert_eq!(
            rec.meta["suite_missed"],
            "worse than the baseline by 3 sigma, beyond 3 reported sigma"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_directory_that_cannot_be_made_is_an_error() {
        let file = std::env::temp_dir().join(format!("nf-keep-file-{}", std::process::id()));
        std::fs::write(&file, "").unwrap();
        let err = Keeper::new(&file.join("sub")).err().unwrap();
        assert!(err.starts_with("--keep "), "{err}");
        std::fs::remove_file(&file).unwrap();
    }
}
