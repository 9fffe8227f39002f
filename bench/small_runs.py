#!/usr/bin/env python3
"""`nf fit` on runs of few positions, written apart from the twin from the documented format:
white Gaussian noise (0.06 deg/h per quarter, 0.03 deg/h per 10 s dwell mean), positions
evenly over a turn, 12 s apart, random latitude (-60 to 60 deg) and azimuth; with and
without the quarter columns. Per row: recordings said to be unresolved, RMS of error/sigma
over the rest, the share within 1 sigma (0.68 for an honest sigma) and the count beyond 3.

    python3 bench/small_runs.py RUNS NF [NF ...]
"""
import json, math, os, random, subprocess, sys, tempfile

WE = 15.041067


def write(path, n, seed, quarters):
    r = random.Random(seed)
    lat, psi = r.uniform(-60, 60), r.uniform(0, 360)
    cols = "index,t_s,encoder_deg,rate_dph" + (",q1_dph,q2_dph,q3_dph,q4_dph" if quarters else "")
    lines = ["# format = northfinder-recording/1", f"# latitude_deg = {lat:.6f}", "# dwell_s = 10", cols]
    for i in range(n):
        g = i * 360 / n
        rate = WE * math.cos(math.radians(lat)) * math.cos(math.radians(g + psi)) + 1.0
        q = [rate + r.gauss(0, 0.06) for _ in range(4)]
        cells = [str(i), str(5 + 12 * i), f"{g:.6f}", f"{sum(q) / 4:.9f}"]
        lines.append(",".join(cells + ([f"{v:.9f}" for v in q] if quarters else [])))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return psi


def z_of(nf, path, psi):
    out = subprocess.run([nf, "fit", path, "--json"], capture_output=True, text=True, check=True)
    j = json.loads(out.stdout)
    if j["azimuth_deg"] is None:
        return None
    return ((j["azimuth_deg"] - psi + 180) % 360 - 180) * 3600 / j["sigma_arcsec"]


def main():
    runs, nfs = int(sys.argv[1]), sys.argv[2:]
    with tempfile.TemporaryDirectory() as tmp:
        for quarters in (False, True):
            for n in (4, 5, 6, 8):
                cases = []
                for s in range(runs):
                    path = os.path.join(tmp, f"n{n}_{int(quarters)}_{s}.csv")
                    cases.append((path, write(path, n, 1000 * n + s, quarters)))
                row = []
                for nf in nfs:
                    zs = [z_of(nf, p, psi) for p, psi in cases]
                    ok = [z for z in zs if z is not None]
                    rms = math.sqrt(sum(z * z for z in ok) / len(ok))
                    within = sum(abs(z) < 1 for z in ok) / len(ok)
                    beyond = sum(abs(z) > 3 for z in ok)
                    row.append(f"unresolved {len(zs) - len(ok)}, RMS z {rms:.2f}, within 1 sigma {within:.2f}, beyond 3 {beyond}")
                print(f"n = {n}, quarters {'yes' if quarters else 'no'}: " + " | ".join(row), flush=True)


if __name__ == "__main__":
    main()
