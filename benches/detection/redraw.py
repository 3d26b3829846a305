"""Fresh noise draws of one generated record's truth: the same parameters, protocol and sampling
(the record's own random stream), the noise drawn from another seed per draw. What a record's
verdict would be under other noise of the same kind — the spread the null calibration must match.

    python3 benches/detection/redraw.py --seed 1 --index 26 --draws 8 --out /tmp/redraw26
    python3 benches/detection/redraw.py --outside --seed 38 --index 58 --draws 8 --out /tmp/redraw58 \\
        --drop encoder_noise

Writes OUT/draw_K.csv (K = 0 … draws−1) and OUT/original.csv (the record as the set has it, to
check the stream: it must equal the set's file). `--drop` removes noise features (comma
separated: encoder_noise, ar1_noise, spikes, pink_noise) from the draws; `--ar1-tau` fixes the
AR(1) time constant (s) instead of drawing it.
"""
import argparse
from pathlib import Path

import numpy as np

import generate as g


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seed", type=int, required=True, help="the set's seed")
    ap.add_argument("--index", type=int, required=True, help="the record's index (rec_INDEX.csv)")
    ap.add_argument("--outside", action="store_true", help="a record of the --outside set")
    ap.add_argument("--draws", type=int, default=8)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--drop", default="", help="noise features left out of the draws")
    ap.add_argument("--ar1-tau", type=float, help="fixed AR(1) time constant, s")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    if args.outside:
        spec = g.plan_outside(np.random.default_rng(args.seed), list(g.OUTSIDE))[args.index]
        make = g.make_outside_record
    else:
        spec = g.plan(np.random.default_rng(args.seed), False)[args.index]
        make = g.make_record
    drop = {d for d in args.drop.split(",") if d}
    original_noise = g.add_noise

    def write(name, rec):
        np.savetxt(args.out / name, rec["table"], fmt="%.17g", delimiter=",",
                   header="time_s,load_point_um,mu", comments="")

    write("original.csv", make(spec, np.random.default_rng([args.seed, args.index])))
    for k in range(args.draws):
        def noise(rng, feats, ts, mu, lp, _k=k):
            rng_k = np.random.default_rng([999, _k])
            kept = [f for f in feats if f not in drop]
            if args.ar1_tau is not None:
                rng_k = FixedTau(rng_k, args.ar1_tau)
            return original_noise(rng_k, kept, ts, mu, lp)
        g.add_noise = noise
        write(f"draw_{k}.csv", make(spec, np.random.default_rng([args.seed, args.index])))
        g.add_noise = original_noise
    print(f"{args.draws} draws of {'outside ' if args.outside else ''}seed {args.seed} record "
          f"{args.index} ({spec}) -> {args.out}")


class FixedTau:
    """A random generator whose draw of the AR(1) time constant (`uniform(1, 5)` in
    `generate.add_noise`) is fixed; every other draw is the generator's."""

    def __init__(self, rng, tau):
        self.rng, self.tau = rng, tau

    def uniform(self, lo=0.0, hi=1.0, size=None):
        if (lo, hi) == (1, 5) and size is None:
            return self.tau
        return self.rng.uniform(lo, hi, size)

    def __getattr__(self, name):
        return getattr(self.rng, name)


if __name__ == "__main__":
    main()
