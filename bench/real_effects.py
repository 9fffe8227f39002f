#!/usr/bin/env python3
"""`nf diagnose` on a real gyro's noise with one catalogue effect concealed, written apart
from the twin (numpy, the documented format): named first, false alarms, finals beyond 3
reported sigma and worse than the baseline by 3 of its sigma, per effect.

    python3 bench/real_effects.py NF_BINARY LOG [RUNS] [--stretch S] [--pairs] [--effect NAME]
                                  [--keep DIR] [--fit] [--positions 36,48,72]
                                  [--short quarters|spread|none]

The gyro error of each recording is a window of LOG (the static-log format), its mean
removed and scaled so that its Allan deviation at a dwell is 0.01 deg/h (`s`, as
`examples/real_noise_bench.rs` does), plus the exact Earth rate at a random latitude (-60
to 60) and azimuth. 36, 48 or 72 positions of 1 s, 1.35 s apart, in a sweep (or opposite
pairs); STRETCH s of the log make one second of the recording. The effects at the suite's
moderate level (docs/diagnose.md), in units of `s` or of the quantity's standard error.
`--fit` puts them through `nf fit` instead: RMS error/sigma, how many beyond 3 sigma, and
white least squares' RMS error/sigma over the recordings resolved, and how many `nf fit` said
unresolved. `--positions` cycles through other run sizes; `--short`
writes the window's sample spread (`rate_sd_dph`, `samples`) or nothing in place of the
quarter means. `--keep DIR` keeps the recordings whose final is worse than the baseline or beyond 3 sigma;
the shaft tilt is 0.002 deg unless `TILT_DEG` says otherwise; `NO_TEMP=1` leaves the temperature
column out.

The physics, written here apart from the twin: the gyro axis and the inclinometer's Y axis
turned by the shaft tilt about a horizontal axis (Rodrigues), the rate the Earth rate along
the axis and the readings their elevations plus a mounting offset and 0.0005 deg of noise;
the bias linear in the recorded temperature (a ramp and a cycle of 1.5-3 periods per run);
a nonlinearity `k rate^2`; an encoder error in the second harmonic of the encoder angle; a
settling excess in the first quarter after each move; an outlier as a whole dwell shifted.
"""
import json, math, os, subprocess, sys, tempfile
import numpy as np

WE, DWELL, SPACING, S = 15.041, 1.0, 1.35, 0.01
SHORT_COLS = {"quarters": ["q1_dph", "q2_dph", "q3_dph", "q4_dph"], "spread": ["rate_sd_dph", "samples"], "none": []}
SHORT = "quarters"
POSITIONS = [36, 48, 72]
# `NO_TEMP=1`: the temperature column left out (its bias cycle stays where concealed).
NO_TEMP = os.environ.get("NO_TEMP") == "1"
EFFECTS = ["clean", "bias_drift", "bias_jump", "thermal_drift", "shaft_tilt", "encoder_error",
           "scale_factor", "nonlinearity", "settling_transient", "outliers"]


def read_log(path):
    """The rates of a static log and its sample rate (from `t_s`)."""
    with open(path) as f:
        lines = [l for l in f if not l.startswith("#")]
    cols = lines[0].strip().split(",")
    rows = np.array([[float(v) for v in l.split(",")] for l in lines[1:] if l.strip()])
    t = rows[:, cols.index("t_s")]
    return rows[:, cols.index("rate_dph")], round(1 / np.median(np.diff(t)), 3)


def adev(x, m):
    c = np.concatenate([[0.0], np.cumsum(x)])
    means = (c[m:] - c[:-m]) / m
    d = means[m:] - means[:-m]
    return math.sqrt(0.5 * np.mean(d * d))


def tilted(v, eta, toward):
    """`v` (east, north, up) turned by `eta` rad about the horizontal axis at `toward` rad."""
    k = np.array([math.sin(toward), math.cos(toward), 0.0])
    return v * math.cos(eta) + np.cross(k, v) * math.sin(eta) + k * (k @ v) * (1 - math.cos(eta))


def write(path, noise, per_s, n, pairs, effect, rng):
    lat = rng.uniform(-60, 60)
    psi = rng.uniform(0, 360)
    bias = rng.uniform(-1, 1)
    amp = WE * math.cos(math.radians(lat))
    earth = WE * np.array([0.0, math.cos(math.radians(lat)), math.sin(math.radians(lat))])
    step = 360 / n
    start = rng.uniform(0, 360)
    at = lambda k: (start + step * k) % 360
    gammas = ([g for k in range(n // 2) for g in (at(k), (at(k) + 180) % 360)] if pairs
              else [at(k) for k in range(n)])
    T = n * SPACING
    se = S * math.sqrt(2 / n)
    jump_at = rng.uniform(0.3, 0.7) * T
    periods = rng.uniform(1.5, 3)
    phase = rng.uniform(0, 2 * math.pi)
    enc_phase = rng.uniform(0, 2 * math.pi)
    enc_e = 4 * S / amp  # rad: the rate error R e of 4 s
    eta, toward = (float(os.environ.get("TILT_DEG", "0.002")) * math.pi / 180, rng.uniform(0, 2 * math.pi))
    off_x, off_y = rng.normal(0, 0.01, 2)
    scale = 1 + 5 * se / amp
    k2 = 5 * se * 2 / amp**2  # rate^2 coefficient whose 2 psi harmonic is 5 standard errors
    bad = int(rng.integers(n))
    sign = rng.choice([-1, 1])
    q_len = int(DWELL * per_s / 4)
    temp_col = [] if NO_TEMP else ["temp_c"]
    cols = ["index", "t_s", "encoder_deg", "rate_dph"] + SHORT_COLS[SHORT] + temp_col + ["tilt_x_deg", "tilt_y_deg"]
    lines = ["# format = northfinder-recording/1", f"# latitude_deg = {lat:.5f}",
             f"# dwell_s = {DWELL}", ",".join(cols)]
    for i, g in enumerate(gammas):
        t = i * SPACING + DWELL / 2
        temp = 25 + 0.3 * t / T + 1.0 * math.sin(2 * math.pi * periods * t / T + phase)
        tilt = eta if effect == "shaft_tilt" else 0.0
        a = math.radians(-(g + psi))  # the gyro axis' azimuth, clockwise from north
        u = tilted(np.array([math.sin(a), math.cos(a), 0.0]), tilt, toward)
        b = math.radians(-(g + 90 + psi))
        v = tilted(np.array([math.sin(b), math.cos(b), 0.0]), tilt, toward)
        rate = earth @ u
        if effect == "scale_factor":
            rate *= scale
        if effect == "nonlinearity":
            rate += k2 * rate * rate
        rate += bias
        if effect == "bias_drift":
            rate += 4 * S * (t / T - 0.5)
        if effect == "bias_jump" and t > jump_at:
            rate += 3 * S
        if effect == "thermal_drift":
            rate += 2.5 * S * (temp - 25)
        if effect == "outliers" and i == bad:
            rate += sign * 6 * S
        frm = int(i * SPACING * per_s)
        q = np.array([rate + noise[frm + j * q_len: frm + (j + 1) * q_len].mean() for j in range(4)])
        if effect == "settling_transient" and i > 0:
            q[0] += 0.8 * 2 * S
        enc = g
        if effect == "encoder_error":
            enc = (g + math.degrees(enc_e) * math.sin(2 * math.radians(g) + enc_phase)) % 360
        tx = math.degrees(math.asin(u[2])) + off_x + rng.normal(0, 5e-4)
        ty = math.degrees(math.asin(v[2])) + off_y + rng.normal(0, 5e-4)
        seg = noise[frm: frm + 4 * q_len]
        short = {"quarters": [f"{x:.8f}" for x in q], "spread": [f"{seg.std(ddof=1):.8f}", str(len(seg))],
                 "none": []}[SHORT]
        row = [str(i), f"{t:.3f}", f"{enc:.6f}", f"{q.mean():.8f}"] + short
        row += ([] if NO_TEMP else [f"{temp:.4f}"]) + [f"{tx:.6f}", f"{ty:.6f}"]
        lines.append(",".join(row))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return psi


NOISE_TERMS = ("bias_instability", "rate_random_walk", "correlated_noise", "heavy_tails")


def err(az, psi):
    return ((az - psi + 180) % 360 - 180) * 3600


def recordings(path, raw, per_s, runs, pairs, effect, stretch):
    """Writes each recording of a row to `path` in turn, yielding its number and truth."""
    rng = np.random.default_rng([EFFECTS.index(effect), int(stretch * 10), int(pairs)])
    scale = S / adev(raw, int(round(DWELL * per_s)))
    for r in range(runs):
        n = POSITIONS[r % len(POSITIONS)]
        length = int((n * SPACING + DWELL) * per_s)
        frm = int(rng.integers(len(raw) - length))
        w = raw[frm:frm + length]
        yield r, write(path, (w - w.mean()) * scale, per_s, n, pairs, effect, rng)


def diagnose_row(nf, path, rows, effect, keep):
    first = alarms = beyond = worse = runs = 0
    b2 = f2 = 0.0
    named = {}
    for r, psi in rows:
        out = subprocess.run([nf, "diagnose", path, "--json"], capture_output=True, text=True)
        if out.returncode != 0:
            print("failed:", out.stderr.strip()[:200])
            continue
        d = json.loads(out.stdout)
        names = [f["effect"] for f in d["findings"] if f["effect"] not in NOISE_TERMS]
        for x in names:
            named[x] = named.get(x, 0) + 1
        first += bool(names) and names[0] == effect
        alarms += bool(names) and effect == "clean"
        eb = err(d["baseline"]["azimuth_deg"], psi)
        ef = err(d["final"]["azimuth_deg"], psi)
        off = abs(ef) > 3 * d["final"]["sigma_arcsec"]
        bad = abs(ef) > abs(eb) + 3 * d["baseline"]["sigma_arcsec"]
        beyond += off
        worse += bad
        if keep and (off or bad):
            os.replace(path, os.path.join(keep, f"{effect}-{r}-psi{psi:.5f}.csv"))
        b2 += eb * eb
        f2 += ef * ef
        runs += 1
    print(f"{effect:<20} {runs:>4} {first:>12} {alarms:>7} {beyond:>7} {worse:>6}"
          f" {math.sqrt(b2 / runs):>8.1f}\" {math.sqrt(f2 / runs):>8.1f}\"  "
          + ", ".join(f"{k} x{v}" for k, v in sorted(named.items())), flush=True)


def fit_row(nf, path, rows, effect):
    z, white, unresolved = [], [], 0
    for _, psi in rows:
        f = json.loads(subprocess.run([nf, "fit", path, "--json"], capture_output=True,
                                      text=True, check=True).stdout)
        if f["azimuth_deg"] is None:
            unresolved += 1
            continue
        e = err(f["azimuth_deg"], psi)
        z.append(e / f["sigma_arcsec"])
        # Three positions leave no residual, and white least squares no sigma.
        if f["ols"]["sigma_arcsec"] is not None:
            white.append(e / f["ols"]["sigma_arcsec"])
    z, white = np.array(z), np.array(white)
    rms_white = f"{np.sqrt(np.mean(white * white)):.2f}" if len(white) else "-"
    print(f"{effect:<20} {len(z):>4} {np.sqrt(np.mean(z * z)):>10.2f} {np.sum(abs(z) > 3):>7}"
          f" {rms_white:>15} {unresolved:>10}", flush=True)


def main():
    args = sys.argv[1:]
    opt = lambda name, default: args[args.index(name) + 1] if name in args else default
    nf, log = args[0], args[1]
    runs = int(args[2]) if len(args) > 2 and args[2].isdigit() else 20
    stretch = float(opt("--stretch", "1"))
    pairs = "--pairs" in args
    effects = [opt("--effect", None)] if "--effect" in args else EFFECTS
    keep = opt("--keep", None)
    fit = "--fit" in args
    global SHORT, POSITIONS
    SHORT = opt("--short", SHORT)
    POSITIONS = [int(v) for v in opt("--positions", ",".join(map(str, POSITIONS))).split(",")]
    raw, rate_hz = read_log(log)
    print(f"{log}: stretch {stretch}, {'pairs' if pairs else 'sweep'}, {runs} per row")
    if fit:
        print(f"{'effect':<20} runs  RMS z fit  beyond  RMS z white LS  unresolved")
    else:
        print(f"{'effect':<20} runs  named first  alarms  beyond  worse  rms base  rms final  named")
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "r.csv")
        for effect in effects:
            rows = recordings(path, raw, rate_hz * stretch, runs, pairs, effect, stretch)
            if fit:
                fit_row(nf, path, rows, effect)
            else:
                diagnose_row(nf, path, rows, effect, keep)


if __name__ == "__main__":
    main()
