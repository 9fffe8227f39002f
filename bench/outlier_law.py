#!/usr/bin/env python3
"""The outlier test's law under heavy tails, in a model of it (numpy, scipy), the rule of
`crates/nf/src/diagnose/outliers.rs` and `tails.rs` against the exact marginal law of a
studentised value under each Student-t.

    python3 bench/outlier_law.py [RUNS] [BURST_RUNS]

A sweep of n dwell means under `C + A cos + B sin` (n 36 and 72), the largest externally
studentised residual, its tails weighed as `tails.rs` does (a Student-t of 2.5 to 30 dof by
maximum likelihood on the residuals with the largest held out, half the prior on the
normal), and its p-value Bonferroni over the positions:
- today's: under a t of nu dof the studentised value is scaled by sqrt(nu / (nu - 2)), as if
  the rest's RMS were the noise's sd;
- exact: the probability that a t value exceeds the studentised value times the rest's RMS
  of `dof` unit t draws, averaged over 2000 draws of that RMS (under heavy tails the RMS is
  mostly below the sd, which today's rule leaves out).
Printed: the share of clean runs named an outlier at 0.005 and 0.01 (normal, Student-t 3
and 5, and the suite's heavy tails: normal plus a t3 shift of 0.3-3 sd) and the share of runs
with a burst of 6 or 10 sd found at its position.
"""
import sys
import numpy as np
from scipy import special, stats

DOF = np.array([2.5, 3, 4, 5, 7, 10, 15, 30.0])
LEVELS = (0.005, 0.01)


def student_ll(r, nu, s2):
    for _ in range(50):
        nxt = np.mean(r * r * (nu + 1) / (nu + r * r / s2))
        done = abs(nxt - s2) <= 1e-12 * s2
        s2 = nxt
        if done:
            break
    c = special.gammaln((nu + 1) / 2) - special.gammaln(nu / 2) - 0.5 * np.log(nu * np.pi * s2)
    return np.sum(c - (nu + 1) / 2 * np.log1p(r * r / (nu * s2)))


def tail_weights(resid, held):
    r = np.delete(resid, held)
    s2 = np.mean(r * r)
    normal = -0.5 * len(r) * (np.log(2 * np.pi * s2) + 1)
    ll = np.array([student_ll(r, nu, s2) for nu in DOF])
    top = max(ll.max(), normal)
    t = 0.5 / len(DOF) * np.exp(ll - top)
    wn = 0.5 * np.exp(normal - top)
    return t / (t.sum() + wn), wn / (t.sum() + wn)


RMS = {}


def rms_draws(nu, dof):
    if (nu, dof) not in RMS:
        u = np.random.default_rng(12345).standard_t(nu, (2000, dof))
        RMS[(nu, dof)] = np.sqrt(np.mean(u * u, axis=1))
    return RMS[(nu, dof)]


def p_one(t, wt, wn, dof, exact):
    p = wn * 2 * stats.t.sf(t, dof)
    for w, nu in zip(wt, DOF):
        if w > 1e-6:
            p += w * (np.mean(2 * stats.t.sf(t * rms_draws(nu, dof), nu)) if exact
                      else 2 * stats.t.sf(t * np.sqrt(nu / (nu - 2)), nu))
    return p


def noise(kind, n, rng):
    if kind == "normal":
        return rng.standard_normal(n)
    if kind in ("t3", "t5"):
        nu = int(kind[1])
        return rng.standard_t(nu, n) / np.sqrt(nu / (nu - 2))
    shift = np.exp(rng.uniform(np.log(0.3), np.log(3)))
    return rng.standard_normal(n) + shift * rng.standard_t(3, n) / np.sqrt(3)


def one(n, kind, burst, rng):
    g = np.radians(np.arange(n) * 360 / n)
    x = np.column_stack([np.ones(n), np.cos(g), np.sin(g)])
    y = noise(kind, n, rng)
    at = rng.integers(n)
    y[at] += burst
    hat = x @ np.linalg.pinv(x)
    e, h, dof = y - hat @ y, np.diag(hat), n - x.shape[1]
    s2 = (e @ e - e * e / (1 - h)) / (dof - 1)
    ti = np.abs(e) / np.sqrt(s2 * (1 - h))
    i = int(np.argmax(ti))
    xi = np.column_stack([x, np.eye(n)[:, i]])
    wt, wn = tail_weights(y - xi @ np.linalg.lstsq(xi, y, rcond=None)[0], i)
    found = burst == 0 or i == at
    return [found and min(1, n * p_one(ti[i], wt, wn, dof - 1, exact)) < level
            for exact in (False, True) for level in LEVELS]


def main():
    runs = int(sys.argv[1]) if len(sys.argv) > 1 else 2000
    burst_runs = int(sys.argv[2]) if len(sys.argv) > 2 else 1000
    print("share named an outlier at 0.005 / 0.01: today's rule, the exact law")
    rows = [(k, 0.0, runs) for k in ("normal", "t3", "t5", "heavy_tails")]
    rows += [("normal", 6.0, burst_runs), ("normal", 10.0, burst_runs), ("heavy_tails", 10.0, burst_runs)]
    for kind, burst, r in rows:
        for n in (36, 72):
            rng = np.random.default_rng([n, int(burst), len(kind)])
            hits = np.mean([one(n, kind, burst, rng) for _ in range(r)], axis=0)
            what = f"{kind}, burst {burst:g} sd" if burst else f"{kind}, clean"
            print(f"{what:<26} n {n:>2}  today {hits[0]:6.1%} / {hits[1]:6.1%}   exact {hits[2]:6.1%} / {hits[3]:6.1%}")


if __name__ == "__main__":
    main()
