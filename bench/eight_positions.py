#!/usr/bin/env python3
"""`nf diagnose` and `nf fit` on eight positions in opposite pairs with the dwell means alone
(no quarters, no samples' spread), written apart from the twin from the documented format:
white noise of 0.01 deg/h per dwell mean, one dwell (at random) off by SIZE deg/h.

    python3 bench/eight_positions.py NF_BINARY SIZE [RUNS]

Prints the RMS of error/sigma, the count beyond 3 sigma and the share within 1.96 sigma of
diagnose's final and of `nf fit`.
"""
import json, math, os, subprocess, sys, tempfile
import numpy as np


def write(path, rng, size):
    lat, psi = rng.uniform(-70, 70), rng.uniform(0, 360)
    amplitude = 15.041 * math.cos(math.radians(lat))
    hit = rng.integers(8)
    lines = ["# format = northfinder-recording/1", f"# latitude_deg = {lat}", "index,t_s,encoder_deg,rate_dph"]
    for k, p in enumerate([0, 4, 1, 5, 2, 6, 3, 7]):
        g = 45.0 * p
        rate = 0.4 + amplitude * math.cos(math.radians(g + psi)) + 0.01 * rng.normal() + (size if k == hit else 0.0)
        lines.append(f"{k},{3 * k + 1},{g},{rate}")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return psi


def z_of(nf, cmd, path, psi):
    out = json.loads(subprocess.run([nf, cmd, path, "--json"], capture_output=True, text=True, check=True).stdout)
    r = out["final"] if cmd == "diagnose" else out
    return ((r["azimuth_deg"] - psi + 180) % 360 - 180) * 3600 / r["sigma_arcsec"]


def main():
    nf, size = sys.argv[1], float(sys.argv[2])
    runs = int(sys.argv[3]) if len(sys.argv) > 3 else 300
    rng = np.random.default_rng(5)
    zs = {"diagnose": [], "fit": []}
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "r.csv")
        for _ in range(runs):
            psi = write(path, rng, size)
            for cmd, z in zs.items():
                z.append(z_of(nf, cmd, path, psi))
    for cmd, z in zs.items():
        rms = math.sqrt(sum(v * v for v in z) / len(z))
        beyond = sum(abs(v) > 3 for v in z)
        within = sum(abs(v) < 1.96 for v in z) / len(z)
        print(f"{cmd}: off by {size} deg/h, {runs} runs: RMS error/sigma {rms:.2f}, beyond 3 sigma {beyond}, within 1.96 sigma {within:.3f}")


main()
