#!/usr/bin/env python3
"""White-noise recordings written apart from the twin (numpy, the documented format), fitted by
`nf fit` and `nf diagnose`: the RMS of error/sigma and the mean sigma against the truth.

    python3 bench/independent_writer.py NF_BINARY [RUNS] [--bare]

A sweep of 36 positions, 2 s dwells 0.8 s apart, 0.005 deg/h of white noise on a dwell mean
(the paper's gyro), latitude 43.8; the quarter, temperature and tilt columns unless --bare.
The truth's sigma is sqrt(2 / n) 0.005 / (WE cos(lat)) rad: 22.4".
"""
import json, math, os, subprocess, sys, tempfile
import numpy as np

WE, LAT, PSI, N, SD, DWELL, GAP = 15.041, 43.8, 65.5378, 36, 0.005, 2.0, 0.8


def write(path, seed, bare):
    rng = np.random.default_rng(seed)
    h = WE * math.cos(math.radians(LAT))
    start = rng.uniform(0, 360 / N)
    cols = ["index", "t_s", "encoder_deg", "rate_dph"]
    if not bare:
        cols += ["q1_dph", "q2_dph", "q3_dph", "q4_dph", "temp_c", "tilt_x_deg", "tilt_y_deg"]
    lines = ["# format = northfinder-recording/1", f"# latitude_deg = {LAT}", ",".join(cols)]
    for k in range(N):
        g = (start + k * 360 / N) % 360
        t = k * (DWELL + GAP) + GAP + DWELL / 2
        # Quarters with twice a dwell mean's noise average to it.
        q = h * math.cos(math.radians(g + PSI)) + 0.3 + 2 * SD * rng.normal(size=4)
        row = [str(k), f"{t:.3f}", f"{g:.5f}", f"{q.mean():.7f}"]
        if not bare:
            # A level shaft 0.002 deg towards 140 deg: X = -eta cos(g - tau), Y = eta sin(g - tau).
            tx = -0.002 * math.cos(math.radians(g - 140)) + 5e-4 * rng.normal()
            ty = 0.002 * math.sin(math.radians(g - 140)) + 5e-4 * rng.normal()
            row += [f"{v:.7f}" for v in q] + [f"{40 + 0.01 * t:.3f}", f"{tx:.5f}", f"{ty:.5f}"]
        lines.append(",".join(row))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


def run(nf, args):
    out = subprocess.run([nf] + args, capture_output=True, text=True, check=True).stdout
    return json.loads(out)


def main():
    nf = sys.argv[1]
    runs = int(sys.argv[2]) if len(sys.argv) > 2 and sys.argv[2].isdigit() else 60
    bare = "--bare" in sys.argv
    err = lambda az: ((az - PSI + 180) % 360 - 180) * 3600
    fit, diag = [], []
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "r.csv")
        for seed in range(1, runs + 1):
            write(path, seed, bare)
            f = run(nf, ["fit", path, "--json"])
            fit.append((err(f["azimuth_deg"]), f["sigma_arcsec"], f["ols"]["sigma_arcsec"]))
            d = run(nf, ["diagnose", path, "--json"])["final"]
            diag.append((err(d["azimuth_deg"]), d["sigma_arcsec"]))
    truth = math.sqrt(2 / N) * SD / (WE * math.cos(math.radians(LAT))) * 180 / math.pi * 3600
    z = lambda rows, i: math.sqrt(sum((r[0] / r[i]) ** 2 for r in rows) / len(rows))
    mean = lambda rows, i: sum(r[i] for r in rows) / len(rows)
    print(f"{runs} recordings, {'bare' if bare else 'all columns'}; truth's sigma {truth:.1f}\"")
    print(f"nf fit:           RMS error/sigma {z(fit, 1):.2f}, mean sigma {mean(fit, 1):.1f}\"")
    print(f"white LS:         RMS error/sigma {z(fit, 2):.2f}, mean sigma {mean(fit, 2):.1f}\"")
    print(f"diagnose final:   RMS error/sigma {z(diag, 1):.2f}, mean sigma {mean(diag, 1):.1f}\"")
    rms = lambda rows: math.sqrt(sum(r[0] ** 2 for r in rows) / len(rows))
    print(f"RMS error: fit {rms(fit):.1f}\", diagnose {rms(diag):.1f}\"")


if __name__ == "__main__":
    main()
