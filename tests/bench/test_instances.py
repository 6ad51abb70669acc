"""Benchmark manifest: the shipped instances, validation of bad entries, selection, targets."""

from __future__ import annotations

import numpy as np
import pytest

from illuknit.bench.instances import (
    DEFAULT_MANIFEST,
    instance_targets,
    load_manifest,
    parse_manifest,
    select_instances,
)
from illuknit.core.errors import ManifestError, UnknownNameError


def entry(**over):
    e = {
        "name": "t",
        "kind": "double",
        "size": [8, 10],
        "yarns": ["#000000", "#ffffff"],
        "time_limit": 1,
        "a": {"draw": "plus"},
        "b": {"draw": "circle"},
    }
    e.update(over)
    return {k: v for k, v in e.items() if v is not None}


def test_shipped_manifest_is_valid_and_covers_the_issue():
    man = load_manifest()
    assert man.path == str(DEFAULT_MANIFEST)
    sizes = [i.size for i in man.instances]
    assert min(min(s) for s in sizes) == 30
    assert (330, 200) in sizes  # the paper's largest piece: 660 x 400 stitches
    assert {len(i.yarns) for i in man.instances} >= {2, 3, 4}
    assert {i.kind for i in man.instances} == {"single", "double"}
    quick = select_instances(man, "quick")
    assert 3 <= len(quick) <= 6 and all(max(i.size) <= 90 for i in quick)


def test_every_shipped_instance_draws_its_targets_offline():
    for inst in load_manifest().instances:
        if inst.size[0] * inst.size[1] > 20000:
            continue  # the big photo pair is exercised by the benchmark itself
        t = instance_targets(inst)
        assert t.a.shape == inst.size and t.b.shape == inst.size
        assert t.a.max() < len(inst.yarns)
        # every target shows more than one colour
        assert len(np.unique(t.a)) >= 2 and len(np.unique(t.b)) >= 2


def test_mask_inputs_use_ink_and_paper():
    inst = parse_manifest(
        {"instance": [entry(a={"draw": "plus", "ink": 1, "paper": 0})]}
    ).instances[0]
    t = instance_targets(inst)
    assert t.a[4, 5] == 1 and t.a[0, 0] == 0  # plus centre is ink
    assert t.b[4, 5] == 0  # default ink is yarn 0


def test_layers_paint_in_order():
    lay = {"layers": [{"draw": "circle", "yarn": 0}, {"draw": "plus", "yarn": 1}], "background": 2}
    inst = parse_manifest(
        {"instance": [entry(yarns=["#000000", "#ff0000", "#ffffff"], a=lay)]}
    ).instances[0]
    t = instance_targets(inst)
    assert t.a[4, 5] == 1 and t.a[0, 0] == 2 and set(np.unique(t.a)) == {0, 1, 2}


def test_image_inputs_are_mapped_to_the_instance_yarns():
    inst = parse_manifest(
        {"instance": [entry(yarns=["#101010", "#808080", "#f0f0f0"], a={"image": "camera"})]}
    ).instances[0]
    t = instance_targets(inst)
    assert t.a.shape == (8, 10) and t.a.max() <= 2


def test_single_view_instance_has_one_target():
    inst = parse_manifest(
        {"instance": [entry(kind="single", a=None, b=None, input={"text": "A"})]}
    ).instances[0]
    t = instance_targets(inst)
    assert np.array_equal(t.a, t.b)


@pytest.mark.parametrize(
    ("over", "match"),
    [
        ({"b": None}, "needs input `b`"),
        ({"size": [8]}, "size"),
        ({"size": [0, 10]}, "size"),
        ({"size": [8, 5000]}, "size"),
        ({"size": "big"}, "size"),
        ({"a": {"draw": "star"}}, "unknown drawing 'star'.*heart"),
        ({"a": {"image": "data_needs_download"}}, "not a bundled scikit-image picture"),
        ({"a": {}}, "exactly one of"),
        ({"a": {"draw": "plus", "text": "x"}}, "exactly one of"),
        ({"a": {"draw": "plus", "ink": 5}}, "yarn index"),
        ({"yarns": ["#000000"]}, "2..6"),
        ({"yarns": ["#000000", "notacolour"]}, "yarns"),
        ({"time_limit": 0}, "time_limit"),
        ({"kind": "triple"}, "kind"),
        ({"name": "Bad Name"}, "name"),
        ({"colour": "red"}, "unknown key"),
        ({"kind": "single"}, "single-view instance needs `input`"),
    ],
)
def test_bad_entries_are_rejected_with_the_reason(over, match):
    with pytest.raises(ManifestError, match=match):
        parse_manifest({"instance": [entry(**over)]})


def test_duplicate_names_and_empty_manifests_are_rejected():
    with pytest.raises(ManifestError, match="twice"):
        parse_manifest({"instance": [entry(), entry()]})
    with pytest.raises(ManifestError, match="at least one"):
        parse_manifest({})


def test_manifest_files(tmp_path):
    with pytest.raises(ManifestError, match="not found"):
        load_manifest(tmp_path / "none.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[[instance]\nname=", encoding="utf-8")
    with pytest.raises(ManifestError, match="not valid TOML"):
        load_manifest(bad)
    good = tmp_path / "good.toml"
    good.write_text(
        '[[instance]]\nname = "x"\nsize = [6, 6]\nyarns = ["black", "white"]\n'
        'tags = ["quick"]\na = { draw = "plus" }\nb = { text = "O" }\n',
        encoding="utf-8",
    )
    man = load_manifest(good)
    assert man.names() == ["x"] and man.instances[0].quick


def test_selection():
    man = parse_manifest(
        {"instance": [entry(name="a1", tags=["quick"]), entry(name="b2"), entry(name="c3")]}
    )
    assert [i.name for i in select_instances(man, "quick")] == ["a1"]
    assert [i.name for i in select_instances(man, "all")] == ["a1", "b2", "c3"]
    assert [i.name for i in select_instances(man, "c3,quick")] == ["a1", "c3"]
    with pytest.raises(UnknownNameError, match="valid: quick, all, a1, b2, c3"):
        select_instances(man, "zz")


def test_instance_round_trips_through_manifest_form_with_the_same_key():
    inst = parse_manifest({"instance": [entry()]}).instances[0]
    again = parse_manifest({"instance": [inst.to_manifest()]}).instances[0]
    assert again.key() == inst.key()
    changed = parse_manifest({"instance": [entry(time_limit=2)]}).instances[0]
    assert changed.key() != inst.key()
