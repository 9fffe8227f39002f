#!/usr/bin/env python3
"""`nf fit` through shocks: twin recordings (`nf simulate`) whose dwell means shocks strike, and
control cases without them; the RMS error, the RMS of error/sigma and the count beyond 3 sigma
of each binary given, and in how many recordings the fit weighed the dwells through shocks.
With --diagnose, of `nf diagnose`'s final azimuth instead.

    python3 bench/shocks.py RUNS NF [NF_BEFORE] [CASE ...] [--diagnose]

CASE is the letter of a case below (all by default). 72 positions of 2 s (36 of 1 s in H), the
paper's gyro (0.005 deg/h for a 2 s mean), latitude 43.8, level, psi drawn per seed.
"""
import json, math, os, random, subprocess, sys, tempfile

SHOCKS = ["--shocks-per-hour", "146", "--shock-size", "0.0866", "--shock-duration", "2"]
CASES = {
    "A": ("shocks 146/h, 0.087 deg/h, 2 s", SHOCKS),
    "B": ("shocks 600/h, 0.015 deg/h, 1 s", ["--shocks-per-hour", "600", "--shock-size", "0.015", "--shock-duration", "1"]),
    "C": ("shocks 40/h, 0.2 deg/h, 0.5 s", ["--shocks-per-hour", "40", "--shock-size", "0.2", "--shock-duration", "0.5"]),
    "D": ("shocks 300/h, 0.01 deg/h, 3 s", ["--shocks-per-hour", "300", "--shock-size", "0.01", "--shock-duration", "3"]),
    "E": ("white", []),
    "F": ("flicker B 0.004 and A's shocks", ["--bias-instability", "0.004"] + SHOCKS),
    "G": ("walk K 0.05 and A's shocks", ["--rrw", "0.05"] + SHOCKS),
    "H": ("A's shocks, 36 dwells of 1 s", ["--n", "36", "--dwell", "1"] + SHOCKS),
    "I": ("Student-t (3 dof) samples", ["--student-t-dof", "3"]),
}


def fit(nf, path, psi, diagnose):
    out = subprocess.run([nf, "diagnose" if diagnose else "fit", path, "--json"], capture_output=True, text=True,
                         check=True).stdout
    j = json.loads(out)
    if diagnose:
        through = any("fitted through shocks" in n for n in j["notes"])
        j = j["final"]
    else:
        through = j["noise_model"].get("shocks") is not None
    err = ((j["azimuth_deg"] - psi + 180) % 360 - 180) * 3600
    return err, j["sigma_arcsec"], through


def main():
    diagnose = "--diagnose" in sys.argv
    args = [a for a in sys.argv[2:] if a != "--diagnose"]
    runs, binaries = int(sys.argv[1]), [a for a in args if len(a) > 1]
    only = [a for a in args if len(a) == 1]
    with tempfile.TemporaryDirectory() as tmp:
        for key, (name, args) in CASES.items():
            if only and key not in only:
                continue
            rows = [[] for _ in binaries]
            fitted = 0
            for seed in range(1, runs + 1):
                random.seed(seed)
                psi = round(random.uniform(0, 360), 4)
                path = os.path.join(tmp, "r.csv")
                subprocess.run([binaries[0], "simulate", *args, "--psi", str(psi), "--seed", str(seed),
                                "--tilt", "0", "-o", path], capture_output=True, check=True)
                for k, nf in enumerate(binaries):
                    e, s, through = fit(nf, path, psi, diagnose)
                    rows[k].append((e, s))
                    fitted += through and k == 0
            cells = []
            for r in rows:
                rms = math.sqrt(sum(e * e for e, _ in r) / len(r))
                z = math.sqrt(sum((e / s) ** 2 for e, s in r) / len(r))
                cells.append(f"rms error {rms:6.1f}\" rms z {z:.2f} beyond 3 sigma {sum(abs(e / s) > 3 for e, s in r)}")
            print(f"{key} {name:32s} through shocks {fitted:3d}/{runs} | " + " | ".join(cells), flush=True)


main()
