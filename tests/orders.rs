//! Visiting orders run by the firmware's logic on the twin: the positions come in the order
//! asked for, and the balanced orders cancel a linear bias drift that biases a single sweep by
//! about `k T / (pi H)`.

use nf_instrument::run::{Fault, RunConfig, TiltPolicy};
use nf_model::EARTH_RATE_DPH;
use nf_model::angle::wrap_180;
use nf_model::noise::NoiseModel;
use nf_model::order::{Order, OrderError};
use nf_twin::{Recorder, TwinConfig, simulate};

const PSI_DEG: f64 = 65.5378;

/// The azimuth a run reports and its dwells' (gamma, t).
fn run(order: Order, drift_dph_per_s: f64) -> (f64, Vec<(f64, f64)>) {
    let mut twin = TwinConfig {
        noise: NoiseModel::WHITE_NONE,
        bias_drift_dph_per_s: drift_dph_per_s,
        incl_noise_deg: 0.0,
        ..TwinConfig::default()
    };
    twin.instrument.psi_deg = PSI_DEG;
    let cfg = RunConfig {
        positions: 72,
        order,
        dwell_ms: 500,
        tilt_policy: TiltPolicy::Warn,
        ..RunConfig::default()
    };
    let mut rec = Recorder::default();
    let (report, _) = simulate(&twin, &cfg, &mut rec);
    assert_eq!(report.result, Ok(()), "{}", order.name());
    let rows = nf::recording::Recording::parse(&rec.text()).unwrap().rows;
    let dwells = rows.iter().map(|r| (r.encoder_deg, r.t_s)).collect();
    (report.azimuth.unwrap().psi_deg as f64, dwells)
}

/// The shift of psi (arcsec) a drift `k` (deg/h per s) gives a least-squares fit of Eq. 7 on
/// dwells that cover the turn evenly: the drift's projection on the first harmonic.
fn predicted_shift_arcsec(dwells: &[(f64, f64)], k: f64, h: f64) -> f64 {
    let n = dwells.len() as f64;
    let (da, db) = dwells.iter().fold((0.0, 0.0), |(a, b), &(g, t)| {
        let g = g.to_radians();
        (a + 2.0 / n * k * t * g.cos(), b + 2.0 / n * k * t * g.sin())
    });
    // psi = atan2(-B, A) with A = H cos(psi), B = -H sin(psi).
    let (a, b) = (h * PSI_DEG.to_radians().cos(), -h * PSI_DEG.to_radians().sin());
    ((b * da - a * db) / (h * h)).to_degrees() * 3600.0
}

#[test]
fn the_run_visits_the_positions_in_the_order_asked() {
    for order in Order::NAMED {
        let (_, dwells) = run(order, 0.0);
        let want: Vec<u16> = order.positions(72).collect();
        assert_eq!(dwells.len(), want.len());
        for ((g, _), p) in dwells.iter().zip(want) {
            assert!(
                wrap_180(g - p as f64 * 5.0).abs() < 0.03,
                "{}: {g} vs {p}",
                order.name()
            );
        }
    }
}

#[test]
fn balanced_orders_cancel_a_linear_drift() {
    let h = EARTH_RATE_DPH * 43.8f64.to_radians().cos();
    let shift = |order: Order| {
        let (clean, dwells) = run(order, 0.0);
        // 0.05 deg/h over the sweep's span, as in a paper-sized run.
        let k = 0.05 / (dwells.last().unwrap().1 - dwells[0].1);
        let (drifted, _) = run(order, k);
        let measured = wrap_180(drifted - clean) * 3600.0;
        let predicted = predicted_shift_arcsec(&dwells, k, h);
        assert!(
            (measured - predicted).abs() < 0.03 * predicted.abs() + 0.3,
            "{}: {measured}\" vs the projection's {predicted}\"",
            order.name()
        );
        eprintln!("{}: drift shifts psi by {measured:.2}\"", order.name());
        measured
    };
    let seq = shift(Order::Sequential);
    assert!(seq.abs() > 50.0, "sequential {seq}");
    let fb = shift(Order::ForwardBack);
    let pairs = shift(Order::OppositePairs);
    let alternating = shift(Order::AlternatingPairs);
    let inter = shift(Order::Interleaved);
    assert!(fb.abs() < 0.01 * seq.abs(), "forward-back {fb}\" vs sequential {seq}\"");
    // Opposite pairs: 2/n of a sweep's effect; alternating pairs: of order 1/n^2.
    assert!(
        pairs.abs() < 2.5 / 72.0 * seq.abs(),
        "opposite pairs {pairs}\" vs sequential {seq}\""
    );
    assert!(
        alternating.abs() < 0.01 * seq.abs(),
        "alternating pairs {alternating}\" vs sequential {seq}\""
    );
    assert!(
        (0.3..0.7).contains(&(inter / seq)),
        "interleaved {inter}\" vs sequential {seq}\""
    );
}

#[test]
fn an_order_that_cannot_visit_the_positions_stops_the_run_before_it_moves() {
    let cfg = RunConfig {
        positions: 9,
        order: Order::OppositePairs,
        ..RunConfig::default()
    };
    let mut rec = Recorder::default();
    let (report, world) = simulate(&TwinConfig::default(), &cfg, &mut rec);
    assert_eq!(report.result.unwrap_err().fault, Fault::Order(OrderError::OddPositions));
    assert_eq!(report.positions, 0);
    assert!(world.t_s() < 0.1, "{}", world.t_s());
    // Two positions, however often: no fit of C, A and B at the end, so no run.
    let cfg = RunConfig {
        positions: 8,
        order: Order::parse("0,4,0,4,0,4").unwrap(),
        ..RunConfig::default()
    };
    let (report, world) = simulate(&TwinConfig::default(), &cfg, &mut Recorder::default());
    assert_eq!(report.result.unwrap_err().fault, Fault::Order(OrderError::FewPositions));
    assert!(world.t_s() < 0.1, "{}", world.t_s());
}
