//! Noise files. On any text: no panic; a model it accepts is valid (finite, non-negative
//! terms, a Gauss-Markov sigma only with its time, Student-t with more than 2 degrees of
//! freedom); written back out it reads as the same model. Model: any valid noise model, written
//! as a noise file (with any one-line comment) reads back exactly; as JSON with its keys (at the
//! top or under `noise_model`; N, B and K always, the others where not zero or by chance), to
//! within serde_json's float parsing (one ulp).
#![no_main]

use arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use nf::noise_file::{KEYS, REQUIRED, parse, write};
use nf_model::noise::NoiseModel;

fn term(u: &mut Unstructured) -> Result<f64> {
    Ok(match u.int_in_range(0..=3u8)? {
        0 => 0.0,
        1 => u.arbitrary::<f64>()?.abs(),
        _ => u.int_in_range(0..=1_000_000u32)? as f64 * 10f64.powi(u.int_in_range(-12..=6)?),
    })
}

fn model(u: &mut Unstructured) -> Result<NoiseModel> {
    let mut m = NoiseModel {
        arw_deg_rth: term(u)?,
        bias_instability_dph: term(u)?,
        rrw_dph_rth: term(u)?,
        gm_sigma_dph: term(u)?,
        gm_tau_s: term(u)?,
        quantization_arcsec: term(u)?,
        student_t_dof: term(u)?,
    };
    if m.validate().is_err() {
        if m.gm_sigma_dph > 0.0 && m.gm_tau_s <= 0.0 {
            m.gm_tau_s = 1.0;
        }
        if m.student_t_dof != 0.0 && m.student_t_dof <= 2.0 {
            m.student_t_dof += 2.5;
        }
    }
    Ok(m)
}

fn values(m: &NoiseModel) -> [f64; 7] {
    [
        m.arw_deg_rth,
        m.bias_instability_dph,
        m.rrw_dph_rth,
        m.gm_sigma_dph,
        m.gm_tau_s,
        m.quantization_arcsec,
        m.student_t_dof,
    ]
}

fn structured(u: &mut Unstructured) -> Result<()> {
    let m = model(u)?;
    if m.validate().is_err() {
        return Ok(());
    }
    // Any comments: the writer keeps each on its line.
    let comments: Vec<String> = u.arbitrary()?;
    let text = write(&m, &comments);
    assert_eq!(parse(&text), Ok(m), "{text}");
    let mut obj = serde_json::Map::new();
    for (k, v) in KEYS.iter().zip(values(&m)) {
        if v != 0.0 || REQUIRED.contains(k) || u.arbitrary()? {
            obj.insert(k.to_string(), serde_json::json!(v));
        }
    }
    let json = if u.arbitrary()? {
        serde_json::json!({ "azimuth_deg": 1.0, "noise_model": obj })
    } else {
        serde_json::Value::Object(obj)
    };
    let json = if u.arbitrary()? {
        serde_json::to_string_pretty(&json)
    } else {
        serde_json::to_string(&json)
    }
    .unwrap();
    // serde_json's default float parser may be one ulp off (its `float_roundtrip` feature is
    // exact): 4.6068399999999997e-7 reads as 4.60684e-7.
    let got = parse(&json).unwrap_or_else(|e| panic!("{e}: {json}"));
    for (g, w) in values(&got).iter().zip(values(&m)) {
        assert!((g - w).abs() <= (2.0 * w * f64::EPSILON).max(1e-323), "{json}: {got:?}");
    }
    Ok(())
}

fuzz_target!(|data: &[u8]| {
    let text = nf_fuzz::text(data);
    if let Ok(m) = parse(&text) {
        assert_eq!(m.validate(), Ok(()));
        let out = write(&m, &["again".to_string()]);
        assert_eq!(parse(&out), Ok(m), "{out}");
    }
    let _ = structured(&mut Unstructured::new(data));
});
