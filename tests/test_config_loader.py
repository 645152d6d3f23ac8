"""The experiment files are read by libyaml's parser where PyYAML has it, else by PyYAML's own: both must give the
same experiments (values, lines), and a malformed file the same message."""

from __future__ import annotations

import shutil

import pytest

from reproductions import api, config


@pytest.mark.skipif(getattr(config, "_FAST_LOADER", None) is None, reason="PyYAML built without libyaml")
def test_both_parsers_give_the_same_experiments(monkeypatch: pytest.MonkeyPatch):
    fast = [api.load(i) for i in api.experiment_ids()]
    monkeypatch.setattr(config, "_FAST_LOADER", None)
    slow = [api.load(i) for i in api.experiment_ids()]
    assert fast == slow  # the values, and each printed entry's place (``where``: file:line of the YAML)
    assert all(p.where.rpartition(":")[2].isdigit() for e in fast for p in e.printed)


@pytest.mark.parametrize("text", ["id: x\nkind: [unclosed\n", "a: 1\n b: 2\n", "- a\nb: c\n", "id: 'open\n"])
def test_a_malformed_file_is_told_the_same_by_either_parser(tmp_path, monkeypatch: pytest.MonkeyPatch, text: str):
    f = tmp_path / "bad.yaml"
    f.write_text(text)
    with pytest.raises(api.InputError) as fast:
        api.load(str(f))
    monkeypatch.setattr(config, "_FAST_LOADER", None)
    with pytest.raises(api.InputError) as slow:
        api.load(str(f))
    assert str(fast.value) == str(slow.value) and "malformed YAML" in str(fast.value)


def test_a_measured_entry_is_checked_like_a_printed_one(tmp_path):
    """A measured row naming no comparison of its kind, or repeating an id, is refused at its line."""
    text = (api.config_dir() / "modern-restitution.yaml").read_text(encoding="utf-8")
    shutil.copytree(api.config_dir() / "data", tmp_path / "data")
    old = "  - id: eps_cushion_low\n"
    assert text.count(old) == 1
    bad = tmp_path / "bad.yaml"
    bad.write_text(text.replace(old, old + "    computed: no_such_comparison\n"), encoding="utf-8")
    with pytest.raises(api.InputError) as info:
        api.load(str(bad))
    line = text[: text.index(old)].count("\n") + 2
    assert f"bad.yaml:{line}" in str(info.value) and "no comparison this kind computes" in str(info.value)
    bad.write_text(text.replace("  - id: eps_cushion_all\n", "  - id: eps_cushion_low\n"), encoding="utf-8")
    with pytest.raises(api.InputError, match="printed and measured ids must be unique; repeated: eps_cushion_low"):
        api.load(str(bad))
