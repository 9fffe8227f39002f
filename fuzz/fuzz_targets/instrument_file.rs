//! Instrument files (TOML). On any text: no panic; a file it accepts twins into a valid noise
//! model and a run whose order fits its positions, and written back out it reads as the same
//! file.
#![no_main]

use libfuzzer_sys::fuzz_target;
use nf::instrument_file::InstrumentFile;

fuzz_target!(|data: &[u8]| {
    let text = nf_fuzz::text(data);
    if let Ok(f) = InstrumentFile::parse(&text) {
        assert_eq!(f.twin().noise.validate(), Ok(()));
        let run = f.run_config();
        assert_eq!(run.order.check(run.positions), Ok(()));
        let out = f.write(&["again".into()]);
        assert_eq!(InstrumentFile::parse(&out).as_ref(), Ok(&f), "{out}");
    }
});
