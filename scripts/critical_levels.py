"""The levels the held-out checks slice: at most N of a mesh's exact
critical heights (evenly picked) and the midpoint between each two
consecutive ones, ascending.

    python3 scripts/critical_levels.py CRITICAL.json N   # one p/q a line

CRITICAL.json is `wmslice critical MESH --format json`. Used by
`heldout.sh` and imported by `heldout_python.py`.
"""

import json
import sys
from fractions import Fraction


def levels(critical, most):
    """`critical`: the parsed JSON document; returns Fractions."""
    zs = [Fraction(c["z"]) for c in critical["critical"]]
    if len(zs) > most:
        zs = [zs[i * (len(zs) - 1) // (most - 1)] for i in range(most)] if most > 1 else zs[:1]
    out = []
    for i, z in enumerate(zs):
        out.append(z)
        if i + 1 < len(zs):
            out.append((z + zs[i + 1]) / 2)
    return out


if __name__ == "__main__":
    with open(sys.argv[1]) as f:
        found = levels(json.load(f), int(sys.argv[2]))
    for z in found:
        print(f"{z.numerator}/{z.denominator}")
