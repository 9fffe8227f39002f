//! The north-finding run of the paper's Sections 2 and 5: levelling check, then for each of
//! `n` positions move (closed on the encoder), settle, dwell, record and update the running
//! azimuth; at the end the fit with the tilt correction and its uncertainty.
//!
//! Nothing here panics: every device fault ends the run in a [`RunError`] that says what and
//! where, and the report keeps the positions measured so far and their fit.

use crate::adc::{AdcError, is_saturated};
use crate::clock::{Clock, with_timeout};
use crate::encoder::{BissEncoder, EncoderError};
use crate::encoder_angle::EncoderAngle;
use crate::inclinometer::{InclError, Inclinometer};
use crate::record::{self, HEADER, Record};
use crate::stepper::{Motor, MotorError};
use crate::white_pool::WhitePool;
use core::fmt::Write as _;
use embedded_hal_async::spi::SpiBus;
use embedded_io_async::{Read, Write};
use nf_model::angle::wrap_360;
use nf_model::dwell::{Calibration, DwellAccumulator};
use nf_model::fit::{AzimuthFit, FitConfig, FitError, FitResult, Obs, vertical_earth_rate_dph};
use nf_model::level::{TiltReading, fit_tilt};
use nf_model::noise::NoiseError;
use nf_model::noise_terms::NoiseTerms;
use nf_model::order::{Order, OrderError};
use nf_model::running::{Running, RunningGls};
use nf_model::text;
use nf_model::tilt_bias::first_order_error_deg;
use nf_model::uncertainty::{self, EARTH_RATE_RATIOS, RESOLVED_SIGMA_DEG};

/// A source of gyro ADC samples (the ADS1256 driver, or the firmware's sample channel).
pub trait GyroSource {
    async fn next_sample(&mut self) -> Result<i32, AdcError>;
    /// Drops samples buffered before now (taken while the shaft moved or settled).
    fn discard_pending(&mut self) {}
    /// Samples lost since the last call (a full queue, a conversion served too late), so that
    /// a dwell can say how many of its samples it did not average.
    fn take_missed(&mut self) -> u32 {
        0
    }
}

impl<SPI: embedded_hal_async::spi::SpiDevice, DRDY: embedded_hal_async::digital::Wait> GyroSource
    for crate::adc::Ads1256<SPI, DRDY>
{
    async fn next_sample(&mut self) -> Result<i32, AdcError> {
        crate::adc::Ads1256::next_sample(self).await
    }
}

/// The gyro temperature sensor.
pub trait Thermometer {
    /// Degrees Celsius, or `None` if the sensor does not answer.
    fn read_c(&mut self) -> Option<f32>;
}

/// Where the run receives its lines and learns of an abort.
pub trait Sink {
    /// One line of the recording (metadata, header or record), without line end.
    async fn line(&mut self, line: &str);
    /// Whether the host asked to abort.
    fn abort_requested(&mut self) -> bool {
        false
    }
}

/// What to do when the levelling check finds the shaft tilted beyond the limit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum TiltPolicy {
    Refuse,
    Warn,
}

/// How often a run looks for an abort while it settles, dwells and moves (the host link's
/// promise: an abort ends the run within 100 ms).
pub const ABORT_CHECKS_PER_S: u32 = 20;

/// Settings of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RunConfig {
    /// Number of equal positions over the turn.
    pub positions: u16,
    /// The order the positions are visited in.
    pub order: Order,
    pub dwell_ms: u32,
    pub settle_ms: u32,
    pub sample_rate_hz: u32,
    pub latitude_deg: f32,
    /// Largest shaft tilt (Eq. 32, at 0 and 180 deg) the levelling check accepts.
    pub tilt_limit_deg: f32,
    pub tilt_policy: TiltPolicy,
    /// A move is done when the encoder is this close to the target.
    pub position_tol_deg: f32,
    /// Corrective moves after the first before the target counts as not reached.
    pub max_corrections: u8,
    /// Remove the vertical Earth rate of each position's inclinometer X reading in the fit.
    pub tilt_correction: bool,
    /// The gyro's noise model for the running azimuth; with no angle random walk the white
    /// part of each dwell mean comes from the samples' spread, pooled over the dwells so far.
    pub noise: NoiseTerms,
    /// End the run once the running sigma under the noise model is at most this, arcsec
    /// (0: visit every position).
    pub target_arcsec: f32,
    pub calibration: Calibration,
}

impl Default for RunConfig {
    fn default() -> Self {
        Self::DEFAULT
    }
}

impl RunConfig {
    /// The paper's run: 72 positions of 2 s at 43.8 deg, levelled to 0.05 deg.
    pub const DEFAULT: RunConfig = RunConfig {
        positions: 72,
        order: Order::Sequential,
        dwell_ms: 2000,
        settle_ms: 300,
        sample_rate_hz: 1000,
        latitude_deg: 43.8,
        tilt_limit_deg: 0.05,
        tilt_policy: TiltPolicy::Refuse,
        position_tol_deg: 0.02,
        max_corrections: 3,
        tilt_correction: true,
        noise: NoiseTerms::NONE,
        target_arcsec: 0.0,
        calibration: Calibration::DEFAULT,
    };
}

/// Where in the run something happened.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Stage {
    Levelling,
    /// Moving to, settling at or dwelling at visit `n` (visiting order, from 0).
    Position(u16),
    Fitting,
}

/// What went wrong.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum Fault {
    /// The settings cannot make a run (no positions, no samples in a dwell).
    BadConfig,
    /// The visiting order cannot visit the positions.
    Order(OrderError),
    /// The noise model is not valid.
    Noise(NoiseError),
    /// The motor was driven but the encoder did not follow.
    Stall {
        commanded_steps: i32,
        moved_counts: i32,
    },
    /// Still off target after all corrective moves.
    NotReached {
        error_counts: i32,
    },
    Motor(MotorError),
    Encoder(EncoderError),
    Inclinometer(InclError),
    /// The gyro ADC sat at full scale.
    AdcSaturated {
        sample: u32,
    },
    /// No sample from the gyro ADC within ten sample periods.
    AdcTimeout {
        sample: u32,
    },
    Adc(AdcError),
    Thermometer,
    /// The levelling check found the shaft tilted beyond the limit (micro-degrees).
    TiltOverLimit {
        tilt_udeg: u32,
        limit_udeg: u32,
    },
    Aborted,
    Fit(FitError),
}

/// A fault and where it happened.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RunError {
    pub stage: Stage,
    pub fault: Fault,
}

/// The azimuth from the positions measured.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Azimuth {
    pub psi_deg: f32,
    /// Standard error of `psi` from the residuals, widened by Student's t for their degrees
    /// of freedom (`t(0.975, dof) / 1.96`: 1.31 at 5, 1.04 at 50), so that 1.96 of it holds
    /// 95 % of errors; `None` (undefined) with no degrees of freedom, when the positions are
    /// as many as the unknowns.
    pub sigma_arcsec: Option<f32>,
    pub amplitude_dph: f32,
    pub offset_dph: f32,
    pub rss: f32,
    pub n: u32,
    pub tilt_corrected: bool,
}

/// The levelling check's result.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct Levelling {
    pub tilt_deg: f32,
    pub tilt_dir_deg: f32,
}

/// Everything a run produced, whether it finished or not.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct RunReport {
    pub result: Result<(), RunError>,
    /// Dwells measured and emitted.
    pub positions: u16,
    /// Gyro samples lost during the dwells (each dwell's are in its `missed` column).
    pub missed_samples: u32,
    pub levelling: Option<Levelling>,
    /// The fit of the positions measured (all of them when the run finished).
    pub azimuth: Option<Azimuth>,
    /// The running azimuth under the noise model.
    pub under_noise: Option<Running<f32>>,
    /// The run ended early: the running sigma reached the target.
    pub target_reached: bool,
    /// The running azimuth resolves the Earth rate at the run's latitude ([`resolved`]);
    /// where not, neither the azimuth nor its sigma can be trusted.
    pub resolved: bool,
}

/// The instrument as the run sees it: the firmware's own drivers on buses and pins.
pub struct Instrument<M, ENC, G, U, T, C> {
    pub motor: M,
    pub encoder: BissEncoder<ENC>,
    pub gyro: G,
    pub inclinometer: Inclinometer<U>,
    pub thermometer: T,
    pub clock: C,
}

fn wrap_counts(d: i64, per_turn: i64) -> i64 {
    let h = per_turn / 2;
    (d + h).rem_euclid(per_turn) - h
}

struct Ctx<'a, M, ENC, G, U, T, C, S> {
    hw: &'a mut Instrument<M, ENC, G, U, T, C>,
    cfg: &'a RunConfig,
    sink: &'a mut S,
    stage: Stage,
    per_turn: i64,
}

impl<M, ENC, G, U, T, C, S> Ctx<'_, M, ENC, G, U, T, C, S>
where
    M: Motor,
    ENC: SpiBus,
    G: GyroSource,
    U: Read + Write,
    T: Thermometer,
    C: Clock,
    S: Sink,
{
    fn err(&self, fault: Fault) -> RunError {
        RunError {
            stage: self.stage,
            fault,
        }
    }

    async fn encoder(&mut self) -> Result<i64, RunError> {
        let r = self.hw.encoder.read().await;
        r.map(|c| c as i64).map_err(|e| self.err(Fault::Encoder(e)))
    }

    /// The angle of `num / den` encoder counts.
    fn angle(&self, num: i64, den: u32) -> Result<EncoderAngle, RunError> {
        // Within range for every encoder the driver reads (32 bits and 20 reads at most).
        EncoderAngle::from_counts(num, den, self.per_turn as u64).ok_or(self.err(Fault::BadConfig))
    }

    async fn tilt(&mut self) -> Result<(f32, f32), RunError> {
        let r = self.hw.inclinometer.read(&mut self.hw.clock).await;
        r.map_err(|e| self.err(Fault::Inclinometer(e)))
    }

    /// Waits the settling time, answering an abort within [`ABORT_CHECKS_PER_S`].
    async fn settle(&mut self) -> Result<(), RunError> {
        let mut left_us = self.cfg.settle_ms as u64 * 1000;
        while left_us > 0 {
            self.check_abort()?;
            let step = left_us.min(1_000_000 / ABORT_CHECKS_PER_S as u64);
            self.hw.clock.delay_us(step).await;
            left_us -= step;
        }
        self.check_abort()
    }

    fn check_abort(&mut self) -> Result<(), RunError> {
        if self.sink.abort_requested() {
            Err(self.err(Fault::Aborted))
        } else {
            Ok(())
        }
    }

    /// Moves to `target` counts, closing the loop on the encoder; returns where it stopped.
    async fn move_to(&mut self, target: i64) -> Result<i64, RunError> {
        let spr = self.hw.motor.steps_per_rev() as i64;
        // Under 1 deg (the settings' range) of at most 2^32 counts: an i32.
        let tol = (self.cfg.position_tol_deg / 360.0 * self.per_turn as f32) as i32 as i64;
        let mut cur = self.encoder().await?;
        for attempt in 0..=self.cfg.max_corrections {
            let err = wrap_counts(target - cur, self.per_turn);
            let steps = (err * spr + self.per_turn.signum() * err.signum() * self.per_turn / 2) / self.per_turn;
            if err.abs() <= tol || steps == 0 {
                return Ok(cur);
            }
            if attempt > 0 {
                debug!("move: correction {} of {} steps", attempt, steps);
            }
            let sink = &mut *self.sink;
            let moved = self
                .hw
                .motor
                .move_steps(steps as i32, &mut || sink.abort_requested())
                .await;
            match moved {
                Ok(()) => {}
                Err(MotorError::Stopped) => return Err(self.err(Fault::Aborted)),
                Err(e) => return Err(self.err(Fault::Motor(e))),
            }
            let new = self.encoder().await?;
            let expected = steps * self.per_turn / spr;
            // How far the encoder fell short of the commanded move (wrap-safe for half turns).
            let short = wrap_counts(new - cur - expected, self.per_turn);
            if short.abs() * 2 > expected.abs() {
                let moved = expected + short;
                error!("move: stall, {} steps commanded, encoder moved {} counts", steps, moved);
                return Err(self.err(Fault::Stall {
                    commanded_steps: steps as i32,
                    moved_counts: moved as i32,
                }));
            }
            cur = new;
        }
        let err = wrap_counts(target - cur, self.per_turn);
        if err.abs() <= tol {
            Ok(cur)
        } else {
            Err(self.err(Fault::NotReached {
                error_counts: err as i32,
            }))
        }
    }

    async fn levelling(&mut self) -> Result<Levelling, RunError> {
        let mut readings = [TiltReading {
            gamma_deg: 0.0f32,
            x_deg: 0.0,
            y_deg: 0.0,
        }; 2];
        for (i, half) in [0, self.per_turn / 2].into_iter().enumerate() {
            let at = self.move_to(half).await?;
            self.settle().await?;
            let (x, y) = self.tilt().await?;
            readings[i] = TiltReading {
                gamma_deg: self.angle(at, 1)?.deg(),
                x_deg: x,
                y_deg: y,
            };
        }
        let t = fit_tilt(&readings).map_err(|e| self.err(Fault::Fit(e)))?;
        info!(
            "levelling: shaft tilt {} deg towards {} deg (Eq. 32)",
            t.tilt_deg, t.tilt_dir_deg
        );
        if t.tilt_deg > self.cfg.tilt_limit_deg {
            let fault = Fault::TiltOverLimit {
                tilt_udeg: (t.tilt_deg * 1e6) as u32,
                limit_udeg: (self.cfg.tilt_limit_deg * 1e6) as u32,
            };
            match self.cfg.tilt_policy {
                TiltPolicy::Refuse => {
                    error!(
                        "levelling: tilt over the limit of {} deg, run refused",
                        self.cfg.tilt_limit_deg
                    );
                    return Err(self.err(fault));
                }
                TiltPolicy::Warn => warn!("levelling: tilt over the limit of {} deg", self.cfg.tilt_limit_deg),
            }
        }
        Ok(Levelling {
            tilt_deg: t.tilt_deg,
            tilt_dir_deg: t.tilt_dir_deg,
        })
    }

    /// Dwells at the current position; `target` is the commanded angle in counts.
    async fn dwell(&mut self, index: u16, target: i64, t0: u64) -> Result<Record, RunError> {
        let cfg = self.cfg;
        let expected = (cfg.dwell_ms as u64 * cfg.sample_rate_hz as u64 / 1000) as u32;
        let period_us = 1_000_000 / cfg.sample_rate_hz.max(1) as u64;
        let mut acc = DwellAccumulator::new(expected);
        let abort_every = (cfg.sample_rate_hz / ABORT_CHECKS_PER_S).max(1);
        // The encoder is read ten times over the dwell and averaged.
        let enc_every = (expected / 10).max(1);
        let (mut enc_sum, mut enc_n) = (0i64, 0i64);
        let (mut tilt, mut temp) = ((f32::NAN, f32::NAN), f32::NAN);
        self.hw.gyro.discard_pending();
        // Losses before the dwell are not the dwell's.
        let _ = self.hw.gyro.take_missed();
        let start = self.hw.clock.now_us();
        for i in 0..expected {
            let s = with_timeout(&mut self.hw.clock, 10 * period_us + 10_000, self.hw.gyro.next_sample()).await;
            let s = match s {
                None => return Err(self.err(Fault::AdcTimeout { sample: i })),
                Some(Err(e)) => return Err(self.err(Fault::Adc(e))),
                Some(Ok(s)) => s,
            };
            if is_saturated(s) {
                error!("dwell: ADC saturated at sample {}", i);
                return Err(self.err(Fault::AdcSaturated { sample: i }));
            }
            acc.push(s);
            if i % enc_every == 0 {
                let c = self.encoder().await?;
                enc_sum += wrap_counts(c - target, self.per_turn);
                enc_n += 1;
            }
            if i == expected / 2 {
                tilt = self.tilt().await?;
                temp = self.hw.thermometer.read_c().ok_or(self.err(Fault::Thermometer))?;
            }
            if i % abort_every == 0 {
                self.check_abort()?;
            }
        }
        let t_mid = (start + self.hw.clock.now_us()) / 2 - t0;
        let missed = self.hw.gyro.take_missed();
        if missed > 0 {
            warn!("dwell {}: {} samples missed (the queue overran)", index, missed);
        }
        let cal = cfg.calibration;
        Ok(Record {
            index,
            t_us: t_mid,
            encoder: self.angle(target * enc_n + enc_sum, enc_n as u32)?,
            rate_dph: cal.rate_dph(acc.sum(), acc.samples()),
            rate_sd_dph: cal.sd_dph(nf_model::sqrt(acc.variance())),
            samples: acc.samples(),
            temp_c: temp,
            tilt_x_deg: tilt.0,
            tilt_y_deg: tilt.1,
            quarters_dph: [0, 1, 2, 3].map(|q| {
                let (sum, n) = acc.quarter(q);
                cal.rate_dph(sum, n)
            }),
            missed,
        })
    }

    /// Adds a dwell to the running azimuth under the noise model and logs it.
    fn under_noise(
        &self,
        running: &mut RunningGls<f32>,
        pool: &mut WhitePool,
        rec: &Record,
    ) -> Result<Running<f32>, RunError> {
        let cfg = self.cfg;
        let mut rate = rec.rate_dph;
        if cfg.tilt_correction {
            rate -= vertical_earth_rate_dph(cfg.latitude_deg, rec.tilt_x_deg);
        }
        // No white level given: the samples' spread shows it, pooled over the dwells so far;
        // a sample carries at least the quantisation of one count.
        let white = (cfg.noise.arw_deg_rth == 0.0).then(|| {
            let count = cfg.calibration.dph_per_count();
            pool.add(rec.rate_sd_dph, rec.samples, count * count / 12.0)
        });
        running.add(rec.encoder.deg(), rec.t_us, rate, white).map_err(|_| {
            self.err(Fault::Fit(FitError::NonFinite {
                index: rec.index as u32,
            }))
        })?;
        let r = running.azimuth();
        // Before three dwells the azimuth is the priors' (a sigma of millions of arcsec).
        if r.dwells >= 3 {
            info!(
                "under the noise model: psi {} deg +- {} arcsec after {} dwells",
                r.psi_deg,
                r.sigma_psi_deg * 3600.0,
                r.dwells
            );
        }
        Ok(r)
    }

    async fn header(&mut self) {
        let c = self.cfg;
        // One line at a time: the run's future (RAM fixed at build time on the MCU) then holds
        // one line, not seven.
        for i in 0..7 {
            let l = match i {
                0 => record::meta("format", |l| l.write_str("northfinder-recording/1")),
                1 => record::meta("latitude_deg", |l| text::write_f32(l, c.latitude_deg, 5)),
                2 => record::meta("dwell_s", |l| text::write_units(l, c.dwell_ms as i64, 3)),
                3 => record::meta("sample_rate_hz", |l| text::write_u64(l, c.sample_rate_hz as u64)),
                4 => record::meta("positions", |l| text::write_u64(l, c.positions as u64)),
                5 => record::meta("order", |l| l.write_str(c.order.name())),
                _ => record::meta("firmware", |l| {
                    l.write_str(concat!("nf-instrument ", env!("CARGO_PKG_VERSION")))
                }),
            };
            self.sink.line(&l).await;
        }
        self.sink.line(HEADER).await;
    }
}

/// Whether the running azimuth resolves the Earth rate at `lat_deg`: its amplitude within
/// [`EARTH_RATE_RATIOS`] of the Earth rate's (a scale set a million times off gave an azimuth
/// 113 deg off at a sigma of 5") and its sigma under [`RESOLVED_SIGMA_DEG`]. The amplitude's
/// own sd is not allowed for, as the host's rule does: where it matters the azimuth's sigma
/// is tens of degrees, and the band costs less flash alone.
fn resolved(r: &Running<f32>, lat_deg: f32) -> bool {
    let ratio = r.amplitude_dph / uncertainty::amplitude_dph(lat_deg);
    ratio >= EARTH_RATE_RATIOS.0 as f32
        && ratio <= EARTH_RATE_RATIOS.1 as f32
        && r.sigma_psi_deg < RESOLVED_SIGMA_DEG as f32
}

fn summary(r: &FitResult<f32>) -> Azimuth {
    Azimuth {
        psi_deg: r.psi_deg,
        sigma_arcsec: (r.dof > 0).then(|| r.sigma_psi_deg * 3600.0 * uncertainty::student_widening::<f32>(r.dof)),
        amplitude_dph: r.amplitude_dph,
        offset_dph: r.offset_dph,
        rss: r.rss,
        n: r.n,
        tilt_corrected: r.cfg.tilt_correction_lat_deg.is_some(),
    }
}

/// Removes from both azimuths the error the per-dwell first-order tilt correction leaves on
/// the levelled tilt (`nf_model::tilt_bias`: of order `eta^2 / 4`, 63" at 2 deg), at the
/// positions visited.
fn second_order_tilt(cfg: &RunConfig, lev: &Levelling, report: &mut RunReport) {
    let n = cfg.positions;
    let gammas = (0..report.positions).map(|k| cfg.order.position(n, k) as f32 * 360.0 / n as f32);
    let tilt = (lev.tilt_deg, lev.tilt_dir_deg);
    let error = |psi: f32| first_order_error_deg(cfg.latitude_deg, psi, tilt, gammas.clone()).ok();
    if let Some(a) = report.azimuth.as_mut()
        && let Some(e) = error(a.psi_deg)
    {
        a.psi_deg = wrap_360(a.psi_deg - e);
        info!(
            "tilt: the first order's error of the tilt squared taken off: {} arcsec",
            e * 3600.0
        );
    }
    if let Some(r) = report.under_noise.as_mut()
        && let Some(e) = error(r.psi_deg)
    {
        r.psi_deg = wrap_360(r.psi_deg - e);
    }
}

/// Runs one north finding. The recording goes to `sink` line by line as it is measured.
pub async fn run<M, ENC, G, U, T, C, S>(
    hw: &mut Instrument<M, ENC, G, U, T, C>,
    cfg: &RunConfig,
    sink: &mut S,
) -> RunReport
where
    M: Motor,
    ENC: SpiBus,
    G: GyroSource,
    U: Read + Write,
    T: Thermometer,
    C: Clock,
    S: Sink,
{
    let per_turn = hw.encoder.counts_per_turn() as i64;
    let mut ctx = Ctx {
        hw,
        cfg,
        sink,
        stage: Stage::Levelling,
        per_turn,
    };
    let mut report = RunReport {
        result: Ok(()),
        positions: 0,
        missed_samples: 0,
        levelling: None,
        azimuth: None,
        under_noise: None,
        target_reached: false,
        resolved: false,
    };
    let fit_cfg = FitConfig {
        tilt_correction_lat_deg: cfg.tilt_correction.then_some(cfg.latitude_deg),
        ..Default::default()
    };
    let Ok(mut fit) = AzimuthFit::new(fit_cfg) else {
        report.result = Err(RunError {
            stage: Stage::Levelling,
            fault: Fault::BadConfig,
        });
        return report;
    };
    let no_samples = cfg.dwell_ms as u64 * cfg.sample_rate_hz as u64 / 1000 == 0;
    if cfg.positions == 0 || no_samples || ctx.hw.motor.steps_per_rev() == 0 {
        report.result = Err(RunError {
            stage: Stage::Levelling,
            fault: Fault::BadConfig,
        });
        return report;
    }
    let checked = cfg.order.check(cfg.positions).map_err(Fault::Order).and_then(|()| {
        cfg.noise.validate().map_err(Fault::Noise)?;
        RunningGls::new(&cfg.noise, cfg.dwell_ms as f32 / 1000.0).map_err(|_| Fault::BadConfig)
    });
    let mut running = match checked {
        Ok(r) => r,
        Err(fault) => {
            report.result = Err(RunError {
                stage: Stage::Levelling,
                fault,
            });
            return report;
        }
    };
    if let Some(u) = cfg.order.uneven(cfg.positions) {
        warn!(
            "run: the order visits {} of {} positions, each {} to {} times: a drift cancels only over an even coverage",
            u.visited, cfg.positions, u.least, u.most
        );
    }
    let mut pool = WhitePool::default();
    report.result = async {
        report.levelling = Some(ctx.levelling().await?);
        ctx.header().await;
        let t0 = ctx.hw.clock.now_us();
        for k in 0..cfg.order.visits(cfg.positions) {
            ctx.stage = Stage::Position(k);
            ctx.check_abort()?;
            let p = cfg.order.position(cfg.positions, k) as i64;
            let target = (p * per_turn + cfg.positions as i64 / 2) / cfg.positions as i64;
            ctx.move_to(target).await?;
            ctx.settle().await?;
            let rec = ctx.dwell(k, target, t0).await?;
            ctx.sink.line(&rec.line()).await;
            report.positions = k + 1;
            report.missed_samples += rec.missed;
            let obs = Obs {
                gamma_deg: rec.encoder.deg(),
                t_s: rec.t_us as f32 * 1e-6,
                rate_dph: rec.rate_dph,
                tilt_x_deg: Some(rec.tilt_x_deg),
                weight: 1.0,
            };
            fit.add(&obs).map_err(|e| ctx.err(Fault::Fit(e)))?;
            let r = ctx.under_noise(&mut running, &mut pool, &rec)?;
            report.under_noise = Some(r);
            let sigma_arcsec = r.sigma_psi_deg * 3600.0;
            let target = cfg.target_arcsec > 0.0 && r.dwells >= 4 && sigma_arcsec <= cfg.target_arcsec;
            if target && resolved(&r, cfg.latitude_deg) {
                info!(
                    "target {} arcsec reached after {} dwells: sigma {} arcsec under the noise model",
                    cfg.target_arcsec, r.dwells, sigma_arcsec
                );
                report.target_reached = true;
                break;
            }
        }
        ctx.stage = Stage::Fitting;
        Ok(())
    }
    .await;
    match fit.solve() {
        Ok(r) => report.azimuth = Some(summary(&r)),
        Err(e) if report.result.is_ok() => {
            report.result = Err(RunError {
                stage: Stage::Fitting,
                fault: Fault::Fit(e),
            })
        }
        Err(_) => {}
    }
    if let (true, false, Some(u)) = (cfg.target_arcsec > 0.0, report.target_reached, report.under_noise) {
        warn!(
            "target {} arcsec not reached: sigma {} arcsec after {} dwells",
            cfg.target_arcsec,
            u.sigma_psi_deg * 3600.0,
            u.dwells
        );
    }
    if let (true, Some(lev)) = (cfg.tilt_correction, report.levelling) {
        second_order_tilt(cfg, &lev, &mut report);
    }
    report.resolved = report.under_noise.is_some_and(|r| resolved(&r, cfg.latitude_deg));
    if report.under_noise.is_some() && !report.resolved {
        warn!(
            "result: the Earth rate is not resolved: the running amplitude is not WE cos(lat) within half (a calibration, a latitude or a gyro wrong) or the sigma is 10 deg or more; the azimuth and its sigma cannot be trusted"
        );
    }
    match (&report.result, &report.azimuth) {
        (Ok(()), Some(a)) => match a.sigma_arcsec {
            Some(s) => info!(
                "result: psi {} deg +- {} arcsec, amplitude {} deg/h, rss {} (deg/h)^2, n {}",
                a.psi_deg, s, a.amplitude_dph, a.rss, a.n
            ),
            None => info!(
                "result: psi {} deg, sigma undefined (0 dof), amplitude {} deg/h, n {}",
                a.psi_deg, a.amplitude_dph, a.n
            ),
        },
        (Err(e), _) => error!("run ended: {:?}; {} positions kept", e, report.positions),
        _ => {}
    }
    report
}
