#!/usr/bin/env python3
"""`nf diagnose --sim` on recordings of the very file it is given: how many are said to need
a change to the file (an effect missing, different, or only in the simulation), which
effects, and how many were judged under the file's noise model. Every such change is a false
alarm. The file: `nf simulate [--n N --dwell D]`'s, its recordings seeds 2001 on.

    python3 bench/sim_lacks.py RUNS NF [NF ...] [--n N --dwell D]
"""
import json, os, subprocess, sys, tempfile


def main():
    args = sys.argv[1:]
    plan = []
    for flag in ("--n", "--dwell"):
        if flag in args:
            i = args.index(flag)
            plan += [flag, args[i + 1]]
            del args[i:i + 2]
    runs, nfs = int(args[0]), args[1:]
    with tempfile.TemporaryDirectory() as tmp:
        inst = os.path.join(tmp, "inst.toml")
        subprocess.run([nfs[0], "simulate", *plan, "--save-config", inst, "-o", os.devnull],
                       check=True, capture_output=True)
        for nf in nfs:
            changed, under, names = 0, 0, {}
            for s in range(1, runs + 1):
                rec = os.path.join(tmp, f"r{s}.csv")
                subprocess.run([nfs[0], "simulate", "--config", inst, "--seed", str(2000 + s), "-o", rec],
                               check=True, capture_output=True)
                out = subprocess.run([nf, "diagnose", rec, "--sim", inst, "--json", "--replicates", "0"],
                                     check=True, capture_output=True, text=True)
                sim = json.loads(out.stdout)["simulation"]
                lacking = [p["effect"] for p in sim["physics"]
                           if p["verdict"] in ("Missing", "Different", "OnlyInSimulation")]
                changed += bool(lacking)
                for x in lacking:
                    names[x] = names.get(x, 0) + 1
                under += bool(sim.get("judged_under_file_noise", False))
            print(f"{nf}: {changed} of {runs} said to need a change {names}; judged under the file's noise {under}")


if __name__ == "__main__":
    main()
