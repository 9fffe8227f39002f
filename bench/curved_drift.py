#!/usr/bin/env python3
"""`nf diagnose` on a curved bias drift: twin recordings from an instrument file (48 positions
of 1 s in one sweep, the paper's gyro, latitude 35, psi 120) whose bias drifts as
`linear * t + quadratic * t^2`; the final azimuth's RMS error, RMS error/sigma and the count
beyond 3 reported sigma, for each binary given.

    python3 bench/curved_drift.py RUNS QUADRATIC LINEAR NF [NF_BEFORE]

QUADRATIC in deg/h/s^2, LINEAR in deg/h/s; seeds 101 to 100 + RUNS.
"""
import json, math, os, subprocess, sys, tempfile

INSTRUMENT = """format = "northfinder-instrument/1"
[site]
latitude_deg = 35.0
azimuth_deg = 120.0
[noise]
arw_deg_rth = 0.00011785113019775792
[drift]
linear_dph_per_s = {linear}
quadratic_dph_per_s2 = {quadratic}
[run]
positions = 48
dwell_s = 1.0
settle_s = 0.3
"""


def final_error(nf, config, seed, tmp):
    rec = os.path.join(tmp, f"r{seed}.csv")
    subprocess.run([nf, "simulate", "--config", config, "--seed", str(seed), "-o", rec], check=True, capture_output=True)
    d = json.loads(subprocess.run([nf, "diagnose", rec, "--json"], check=True, capture_output=True, text=True).stdout)
    err = ((d["final"]["azimuth_deg"] - 120.0 + 180.0) % 360.0 - 180.0) * 3600.0
    return err, d["final"]["sigma_arcsec"]


def main():
    runs, quadratic, linear = int(sys.argv[1]), sys.argv[2], sys.argv[3]
    with tempfile.TemporaryDirectory() as tmp:
        config = os.path.join(tmp, "curve.toml")
        with open(config, "w") as f:
            f.write(INSTRUMENT.format(linear=linear, quadratic=quadratic))
        for nf in sys.argv[4:]:
            rows = [final_error(nf, config, 101 + k, tmp) for k in range(runs)]
            rms = math.sqrt(sum(e * e for e, _ in rows) / runs)
            rms_z = math.sqrt(sum((e / s) ** 2 for e, s in rows) / runs)
            beyond = sum(abs(e) > 3 * s for e, s in rows)
            print(f"{nf}: RMS error {rms:.1f}\", RMS error/sigma {rms_z:.2f}, beyond 3 sigma {beyond} of {runs}")


if __name__ == "__main__":
    main()
