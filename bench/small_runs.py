#!/usr/bin/env python3
"""`nf fit` on runs of few positions, written apart from the twin from the documented format:
white Gaussian samples (400 a dwell, 0.6 deg/h each: 0.06 deg/h per quarter, 0.03 deg/h per
10 s dwell mean), positions evenly over a turn, 12 s apart, random latitude (-60 to 60 deg)
and azimuth; the dwell means alone, with the samples' spread (`rate_sd_dph`, `samples`), or
with the quarter columns (the last two also on three positions). Per row: recordings said
to be unresolved, RMS of error/sigma over the rest, the share within 1 sigma (0.68 for an
honest sigma), the count beyond 3 and the median sigma.

    python3 bench/small_runs.py RUNS NF [NF ...]
    python3 bench/small_runs.py RUNS NF --diagnose

`--diagnose`: eight positions (the fewest `nf diagnose` takes) through `nf diagnose`: the runs
where a catalogue effect is named (false alarms: there is none), the final's RMS of
error/sigma and the count beyond 3 sigma.
"""
import json, math, os, random, subprocess, sys, tempfile

WE = 15.041067


SAMPLES = 400
EXTRA = {"bare": "", "spread": ",rate_sd_dph,samples", "quarters": ",q1_dph,q2_dph,q3_dph,q4_dph"}


def write(path, n, seed, kind):
    r = random.Random(seed)
    lat, psi = r.uniform(-60, 60), r.uniform(0, 360)
    cols = "index,t_s,encoder_deg,rate_dph" + EXTRA[kind]
    lines = ["# format = northfinder-recording/1", f"# latitude_deg = {lat:.6f}", "# dwell_s = 10", cols]
    for i in range(n):
        g = i * 360 / n
        rate = WE * math.cos(math.radians(lat)) * math.cos(math.radians(g + psi)) + 1.0
        x = [rate + r.gauss(0, 0.6) for _ in range(SAMPLES)]
        mean = sum(x) / SAMPLES
        sd = math.sqrt(sum((v - mean) ** 2 for v in x) / (SAMPLES - 1))
        k = SAMPLES // 4
        q = [sum(x[j * k:(j + 1) * k]) / k for j in range(4)]
        extra = {"bare": [], "spread": [f"{sd:.9f}", str(SAMPLES)], "quarters": [f"{v:.9f}" for v in q]}[kind]
        lines.append(",".join([str(i), str(5 + 12 * i), f"{g:.6f}", f"{mean:.9f}"] + extra))
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return psi


def z_of(nf, path, psi):
    """Error over sigma and the sigma, arcsec; `None` when unresolved."""
    out = subprocess.run([nf, "fit", path, "--json"], capture_output=True, text=True, check=True)
    j = json.loads(out.stdout)
    if j["azimuth_deg"] is None:
        return None
    return ((j["azimuth_deg"] - psi + 180) % 360 - 180) * 3600 / j["sigma_arcsec"], j["sigma_arcsec"]


NOISE_TERMS = ("bias_instability", "rate_random_walk", "correlated_noise", "heavy_tails")


def diagnose(runs, nf):
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "r.csv")
        for kind in EXTRA:
            alarms, zs = 0, []
            for s in range(runs):
                psi = write(path, 8, 7000 + s, kind)
                out = subprocess.run([nf, "diagnose", path, "--json"], capture_output=True, text=True, check=True)
                j = json.loads(out.stdout)
                alarms += any(f["effect"] not in NOISE_TERMS for f in j["findings"])
                error = ((j["final"]["azimuth_deg"] - psi + 180) % 360 - 180) * 3600
                zs.append(error / j["final"]["sigma_arcsec"])
            rms = math.sqrt(sum(z * z for z in zs) / len(zs))
            print(f"n = 8, {kind}: false alarms {alarms}, final RMS z {rms:.2f}, beyond 3 {sum(abs(z) > 3 for z in zs)}",
                  flush=True)


def main():
    if "--diagnose" in sys.argv:
        return diagnose(int(sys.argv[1]), sys.argv[2])
    runs, nfs = int(sys.argv[1]), sys.argv[2:]
    with tempfile.TemporaryDirectory() as tmp:
        for kind in EXTRA:
            # Three positions leave the dwell means nothing to measure the noise by.
            for n in (3, 4, 5, 6, 8, 10) if kind != "bare" else (4, 5, 6, 8, 10):
                cases = []
                for s in range(runs):
                    path = os.path.join(tmp, f"n{n}_{kind}_{s}.csv")
                    cases.append((path, write(path, n, 1000 * n + s, kind)))
                row = []
                for nf in nfs:
                    got = [z_of(nf, p, psi) for p, psi in cases]
                    ok = [g for g in got if g is not None]
                    zs = [z for z, _ in ok]
                    sigmas = sorted(s for _, s in ok)
                    rms = math.sqrt(sum(z * z for z in zs) / len(zs))
                    within = sum(abs(z) < 1 for z in zs) / len(zs)
                    beyond = sum(abs(z) > 3 for z in zs)
                    row.append(f"unresolved {len(got) - len(ok)}, RMS z {rms:.2f}, within 1 sigma {within:.2f}, "
                               f"beyond 3 {beyond}, median sigma {sigmas[len(sigmas) // 2]:.0f}\"")
                print(f"n = {n}, {kind}: " + " | ".join(row), flush=True)


if __name__ == "__main__":
    main()
