"""Speed of ``illuknit check`` on a 200 x 200-stitch program.

Target: illuknit's own checks (parse + simulation + rules + fabric) < 10 s for 200 x 200
stitches. Also prints the time of the PyPI knitout-interpreter simulator on the same program
(``--no-vm`` skips it; it takes tens of seconds).

Run: ``python benchmarks/check_speed.py [--width 200] [--courses 200] [--no-vm]``
"""

from __future__ import annotations

import argparse
import time

TARGET_S = 10.0


def generate(width: int, courses: int, *, garter: bool) -> str:
    """A clean swatch: hooked tuck cast-on, courses alternating direction, drop at the end.

    ``garter=True`` alternates knit and purl courses by transferring every loop between beds
    before each course, which doubles the operation count and exercises transfers.
    """
    c = "3"
    hi = width - 1
    odd = list(range(hi, -1, -2))
    lines = [
        ";!knitout-2",
        ";;Machine: SWG091N2",
        ";;Gauge: 7",
        ";;Width: 540",
        ";;Carriers: 1 2 3 4 5 6 7 8 9 10",
        ";;Position: Center",
        f"inhook {c}",
        *[f"tuck - f{n} {c}" for n in odd],
        f"miss - f0 {c}",
        *[f"tuck + f{n} {c}" for n in range(width) if n not in odd],
        f"miss + f{hi} {c}",
        *[f"knit - f{n} {c}" for n in range(hi, -1, -1)],
        f"releasehook {c}",
    ]
    bed = "f"
    d = "+"
    for k in range(courses - 1):
        if garter:
            new = "b" if k % 2 == 0 else "f"
            lines += [f"xfer {bed}{n} {new}{n}" for n in range(width)]
            bed = new
        order = range(width) if d == "+" else range(hi, -1, -1)
        lines += [f"knit {d} {bed}{n} {c}" for n in order]
        d = "-" if d == "+" else "+"
    if bed == "b":
        lines += [f"xfer b{n} f{n}" for n in range(width)]
    lines += [f"outhook {c}", *[f"drop f{n}" for n in range(width)]]
    return "\n".join(lines) + "\n"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--width", type=int, default=200)
    ap.add_argument("--courses", type=int, default=200)
    ap.add_argument("--no-vm", action="store_true", help="skip the PyPI simulator")
    ap.add_argument(
        "--vm-garter",
        action="store_true",
        help="also run the PyPI simulator on the garter program (its transfers are very slow there)",
    )
    args = ap.parse_args()

    from illuknit.check import check_knitout

    w, n = args.width, args.courses
    for name, garter in (("stockinette", False), ("garter+xfers", True)):
        text = generate(w, n, garter=garter)
        t0 = time.perf_counter()
        report = check_knitout(text)
        own = time.perf_counter() - t0
        status = "OK" if own < TARGET_S else "SLOW"
        print(
            f"{name:13s} {w}x{n} stitches, {report.n_operations} ops: illuknit checks "
            f"{own:6.2f} s (target < {TARGET_S:.0f} s: {status}); blocking={len(report.blocking)} "
            f"pieces={report.pieces}"
        )
        if not args.no_vm and (not garter or args.vm_garter):
            from illuknit.check.vm import run_vm
            from illuknit.knitout.parse import parse_knitout

            t0 = time.perf_counter()
            vm = run_vm(text, parse_knitout(text))
            vm_s = time.perf_counter() - t0
            print(
                f"{'':13s} PyPI simulator ({vm.versions}): {vm_s:6.2f} s, "
                f"{sum(f.blocking for f in vm.findings)} blocking, pieces={vm.pieces}"
            )


if __name__ == "__main__":
    main()
