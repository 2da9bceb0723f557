"""Census of the bad-input probes of `setsmooth.reliability.bad_input` (issue 7, "Bad input at the door").

Every probe is one public call with one bad argument. Each is classified as

* clear:      a ValueError/TypeError/IndexError raised by setsmooth whose message names the argument;
* wrong name: raised by setsmooth, but the message does not name the argument the user passed;
* deep:       raised from inside NumPy/SciPy/CVXPY/a solver, or a `SolverError`/other exception type;
* silent:     no exception (a NumPy ComplexWarning that drops an imaginary part counts as silent).

Usage: python benchmarks/bad_input_census.py [-v]     (-v lists every probe that is not clear)
Run it with PYTHONPATH set to a checkout to count that checkout.
"""

from __future__ import annotations

import argparse
import os
import re
import sys
import traceback
import warnings
from collections import Counter

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))

import setsmooth  # noqa: E402
from setsmooth.reliability import bad_input  # noqa: E402
from setsmooth.reliability.bad_input import PROBES, Probe  # noqa: E402

_PACKAGE = os.path.dirname(os.path.realpath(setsmooth.__file__))
_PROBES_FILE = os.path.realpath(bad_input.__file__)  # raised in a probe's own code: not setsmooth's refusal
_EARLY = (ValueError, TypeError, IndexError)


def classify(p: Probe) -> tuple[str, str]:
    """(verdict, detail) for one probe."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            p.call()
        except Exception as exc:  # noqa: BLE001 — classifying every failure is the point
            origin = os.path.realpath(traceback.extract_tb(exc.__traceback__)[-1].filename)
            inside = (origin.startswith(_PACKAGE) and os.sep + "solvers" + os.sep not in origin
                      and origin != _PROBES_FILE)
            detail = f"{type(exc).__name__}: {exc}".splitlines()[0][:110]
            if not isinstance(exc, _EARLY) or type(exc).__name__ == "SolverError" or not inside:
                return "deep", detail
            return ("clear" if re.search(p.names, str(exc)) else "wrong name"), detail
    return "silent", "accepted"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-v", "--verbose", action="store_true")
    args = parser.parse_args()
    counts: Counter = Counter()
    for p in PROBES:
        verdict, detail = classify(p)
        counts[verdict] += 1
        if args.verbose and verdict != "clear":
            print(f"{verdict:<11}{p.id:<52}{detail}")
    print(f"setsmooth at {_PACKAGE}")
    print(f"{'probes':<12}{'clear':>7}{'wrong name':>12}{'deep':>7}{'silent':>8}")
    print(f"{len(PROBES):<12}{counts['clear']:>7}{counts['wrong name']:>12}{counts['deep']:>7}"
          f"{counts['silent']:>8}")


if __name__ == "__main__":
    main()
