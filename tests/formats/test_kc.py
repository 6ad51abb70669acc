"""Kniterate k-code: the reference backend's own tests, random programs and illuknit's programs
against ``knitout-to-kcode.js``, and the programs it must refuse."""

from __future__ import annotations

import random
import subprocess
from pathlib import Path

import pytest

from illuknit.core.errors import KcodeError
from illuknit.formats.kc import knitout_to_kc
from tests.conftest import reference_backend

DATA = Path(__file__).parent / "data" / "kniterate"
HEADER = ";!knitout-2\n;;Carriers: 1 2 3 4 5 6\n"


def without_name(kc: str) -> list[str]:
    lines = kc.split("\n")
    return lines[:2] + lines[3:]


@pytest.mark.parametrize("case", sorted(p.stem for p in DATA.glob("*.k")))
def test_reference_backend_tests_reproduced(case: str) -> None:
    expected = (DATA / f"{case}.kc").read_text()
    got = knitout_to_kc((DATA / f"{case}.k").read_text(), name=f"{case}.kc")
    assert without_name(got) == without_name(expected)
    assert got.split("\n")[2] == f"// {case}.kc"


def node_kc(text: str, tmp_path: Path) -> tuple[str | None, str]:
    """The reference backend's .kc for ``text`` (None when it refuses or fails an assertion)."""
    backend = reference_backend("kniterate/knitout-to-kcode.js")
    src, out = tmp_path / "in.k", tmp_path / "out.kc"
    src.write_text(text)
    out.unlink(missing_ok=True)
    r = subprocess.run(
        ["node", str(backend), str(src), str(out)], capture_output=True, text=True, timeout=60
    )
    log = r.stdout + r.stderr
    if r.returncode or "Assertion failed" in log or not out.exists():
        return None, log
    return out.read_text(), log


def assert_same_as_reference(text: str, tmp_path: Path) -> str | None:
    ref, log = node_kc(text, tmp_path)
    if ref is None:
        with pytest.raises(KcodeError):
            knitout_to_kc(text, name="out.kc")
        return None
    got = knitout_to_kc(text, name="out.kc")
    assert without_name(got) == without_name(ref), log[-500:]
    return got


def random_program(seed: int) -> str:
    """A small random Kniterate program: knits, tucks, misses, transfers, splits, racking,
    drops, extensions, on 1-3 carriers (some invalid: then both must refuse)."""
    rng = random.Random(seed)
    carriers = rng.sample("123456", rng.randint(1, 3))
    lines = [HEADER.rstrip("\n")]
    if rng.random() < 0.3:
        lines.append(f";;Position: {rng.choice(['Left', 'Right', 'Keep', 'Center'])}")
    racking = 0.0
    for c in carriers:
        lines.append(f"in {c}")
        lines += [f"knit + f{n} {c}" for n in range(2, 12)]
    for _ in range(rng.randint(10, 60)):
        c = rng.choice(carriers)
        r = rng.random()
        n = rng.randint(1, 14)
        d = rng.choice("+-")
        if r < 0.35:
            lines.append(
                f"{rng.choice(['knit', 'knit', 'tuck', 'miss'])} {d} {rng.choice('fb')}{n} {c}"
            )
        elif r < 0.45:
            k = n - int(racking)
            lines.append(f"xfer f{n} b{k}" if rng.random() < 0.5 else f"xfer b{k} f{n}")
        elif r < 0.5:
            lines.append(f"split {d} f{n} b{n - int(racking)} {c}")
        elif r < 0.58:
            racking = rng.choice([0.0, 0.0, 1.0, -1.0, 0.25, -0.75])
            lines.append(f"rack {racking:g}")
        elif r < 0.62:
            lines.append(f"drop {rng.choice('fb')}{n}")
        elif r < 0.7:
            lines.append(
                rng.choice(
                    [
                        "x-stitch-number 7",
                        "x-speed-number 200",
                        "x-end-pass",
                        "x-roller-advance 150",
                        "x-add-roller-advance 20",
                        "x-xfer-style two-pass",
                        "pause stop here",
                        "x-carrier-spacing 1.5",
                    ]
                )
            )
        else:
            start, stop = sorted(rng.sample(range(1, 15), 2))
            order = range(start, stop + 1) if d == "+" else range(stop, start - 1, -1)
            lines += [f"knit {d} f{k} {c}" for k in order]
    lines.append("rack 0")
    lines += [f"out {c}" for c in carriers]
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("seed", range(12))
def test_random_programs_match_the_reference(seed: int, tmp_path: Path) -> None:
    assert_same_as_reference(random_program(seed), tmp_path)


@pytest.mark.parametrize(
    ("body", "words"),
    [
        ("inhook 3\nknit - f5 3\nreleasehook 3\nouthook 3\n", "hook"),
        ("in 3\nin 4\nknit + f5 3 4\nout 3\nout 4\n", "plating"),
        ("in 3\nknit + fs5 3\nout 3\n", "slider"),
        ("in 3\nknit + f5 3\n", "never taken out"),
        ("in 3\nrack 0.75\nknit + f5 3\nout 3\n", "racking"),
        ("in 3\nknit + f5 3\nknit + f900 3\nout 3\n", "off the Kniterate"),
        ("in 3\nknit + f5 3\nxfer f5 b6\nout 3\n", "aligned"),
        ("in 3\nfrobnicate f5\n", "unknown operation"),
        ("in 3\nknit\t+\tf5\t3\nout 3\n", "tabs"),
    ],
)
def test_refuses_what_it_cannot_write(body: str, words: str) -> None:
    with pytest.raises(KcodeError, match=words):
        knitout_to_kc(HEADER + body, name="x.kc")


def test_refuses_the_shima_header() -> None:
    text = ";!knitout-2\n;;Carriers: 1 2 3 4 5 6 7 8 9 10\nin 3\nknit + f5 3\nout 3\n"
    with pytest.raises(KcodeError, match="1 2 3 4 5 6") as err:
        knitout_to_kc(text, name="x.kc")
    assert err.value.line is not None
