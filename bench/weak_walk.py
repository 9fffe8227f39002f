#!/usr/bin/env python3
"""`nf fit` on sweeps whose gyro wanders as a weak rate random walk (or a Gauss-Markov bias),
written apart from the twin from the documented format: RMS of error/sigma, the count
beyond 3 sigma, how many runs the estimate took for white noise, and the RMS of
error/sigma apart for the runs whose estimate kept flicker and for the others.

    python3 bench/weak_walk.py NF_BINARY [RUNS] [N] [K] [--gm SIGMA TAU]

N positions of 2 s in a sweep, 0.3 s moves, 0.005 deg/h of white noise on a dwell mean (its
quarters twice that), a walk of K deg/h/sqrt(h) (default 0.05) or a Gauss-Markov bias,
simulated at 20 Hz and averaged over each quarter; latitude -70 to 70, random azimuth.
"""
import json, math, subprocess, sys, tempfile
import numpy as np

WE, SD, DWELL, MOVE, STEP = 15.041, 0.005, 2.0, 0.3, 0.05


def bias(rng, t_end, walk, gm):
    n = int(t_end / STEP) + 2
    if gm:
        sigma, tau = gm
        phi = math.exp(-STEP / tau)
        x = np.empty(n)
        x[0] = sigma * rng.normal()
        for i in range(1, n):
            x[i] = phi * x[i - 1] + sigma * math.sqrt(1 - phi * phi) * rng.normal()
        return x
    # K deg/h/sqrt(h): the bias's sd grows as K sqrt(t / 3600 s).
    return np.cumsum(walk * math.sqrt(STEP / 3600.0) * rng.normal(size=n))


def write(path, seed, n, walk, gm):
    rng = np.random.default_rng(seed)
    lat, psi = rng.uniform(-70, 70), rng.uniform(0, 360)
    starts = MOVE + np.arange(n) * (DWELL + MOVE)
    b = bias(rng, starts[-1] + DWELL, walk, gm)
    lines = ["# format = northfinder-recording/1", f"# latitude_deg = {lat}", f"# dwell_s = {DWELL}",
             "index,t_s,encoder_deg,rate_dph,q1_dph,q2_dph,q3_dph,q4_dph"]
    for k in range(n):
        g = 360.0 * k / n
        earth = WE * math.cos(math.radians(lat)) * math.cos(math.radians(g + psi))
        q = []
        for j in range(4):
            a = int((starts[k] + j * DWELL / 4) / STEP)
            q.append(earth + 0.3 + b[a:a + int(DWELL / 4 / STEP)].mean() + 2 * SD * rng.normal())
        lines.append(f"{k},{starts[k] + DWELL / 2:.3f},{g:.6f},{np.mean(q):.9f}," + ",".join(f"{v:.9f}" for v in q))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return psi


def main():
    args = sys.argv[1:]
    gm = None
    if "--gm" in args:
        i = args.index("--gm")
        gm = (float(args[i + 1]), float(args[i + 2]))
        del args[i:i + 3]
    nf = args[0]
    runs = int(args[1]) if len(args) > 1 else 100
    n = int(args[2]) if len(args) > 2 else 36
    walk = float(args[3]) if len(args) > 3 else 0.05
    z, white, flicker = [], 0, []
    with tempfile.TemporaryDirectory() as d:
        path = f"{d}/r.csv"
        for s in range(runs):
            psi = write(path, 7000 + s, n, walk, gm)
            j = json.loads(subprocess.run([nf, "fit", path, "--json"], capture_output=True, text=True, check=True).stdout)
            err = ((j["azimuth_deg"] - psi + 180) % 360 - 180) * 3600
            z.append(err / j["sigma_arcsec"])
            m = j["noise_model"]
            white += m["bias_instability_dph"] == 0 and m["rrw_dph_rth"] == 0
            flicker.append(m["bias_instability_dph"] > 0)
    z, flicker = np.array(z), np.array(flicker)
    rms = lambda v: math.sqrt(np.mean(v * v)) if len(v) else float("nan")
    what = f"Gauss-Markov {gm[0]} deg/h, {gm[1]} s" if gm else f"walk K {walk}"
    print(f"{what}, n {n}, {runs} runs: RMS error/sigma {math.sqrt(np.mean(z * z)):.2f}, "
          f"beyond 3 sigma {int(np.sum(abs(z) > 3))}, estimated white {white}; "
          f"flicker kept in {int(flicker.sum())} (RMS error/sigma {rms(z[flicker]):.2f}, "
          f"the others {rms(z[~flicker]):.2f})")


main()
