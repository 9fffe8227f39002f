#!/usr/bin/env python3
"""`nf diagnose --sim` on recordings of the file it is given: each compared quantity's z over
the recordings (mean near 0 and sd near 1 when the replays are honest and the recordings'
own), and how many recordings had a mismatch. The file: `nf simulate --n 48 --dwell 1`'s,
its recordings seeds 1001 on.

    python3 bench/sim_spread.py RUNS NF [NF ...]
"""
import json, os, statistics, subprocess, sys, tempfile


def spread(nf, runs, tmp):
    inst = os.path.join(tmp, "inst.toml")
    subprocess.run([nf, "simulate", "--n", "48", "--dwell", "1", "--save-config", inst, "-o", os.devnull],
                   check=True, capture_output=True)
    zs, mismatched = {}, 0
    for s in range(1, runs + 1):
        rec = os.path.join(tmp, f"r{s}.csv")
        subprocess.run([nf, "simulate", "--config", inst, "--seed", str(1000 + s), "-o", rec], check=True, capture_output=True)
        out = subprocess.run([nf, "diagnose", rec, "--sim", inst, "--json"], check=True, capture_output=True, text=True)
        before = json.loads(out.stdout)["simulation"]["before"]
        mismatched += before["mismatches"] > 0
        for q in before["quantities"]:
            zs.setdefault(q["quantity"], []).append(q["z"])
    print(f"{nf}: recordings with a mismatch {mismatched} of {runs}")
    for k, v in zs.items():
        print(f"  {k:<24} z mean {statistics.mean(v):+.2f} sd {statistics.stdev(v):.2f}")


def main():
    runs = int(sys.argv[1])
    for nf in sys.argv[2:]:
        with tempfile.TemporaryDirectory() as tmp:
            spread(nf, runs, tmp)


if __name__ == "__main__":
    main()
