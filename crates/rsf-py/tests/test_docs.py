"""docs/python.md's walk-through, executed block after block in one namespace."""

import os
import re

import pytest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))


def test_the_walkthrough_runs_as_written(monkeypatch):
    pytest.importorskip("matplotlib")
    text = open(os.path.join(ROOT, "docs", "python.md"), encoding="utf-8").read()
    section = text[text.index("## A walk-through"):text.index("## Speed")]
    blocks = re.findall(r"```python\n(.*?)```", section, flags=re.S)
    assert len(blocks) >= 5
    monkeypatch.chdir(ROOT)
    os.makedirs("target", exist_ok=True)
    ns: dict = {}
    for i, code in enumerate(blocks):
        exec(compile(code, f"docs/python.md block {i + 1}", "exec"), ns)
    assert os.path.exists("target/python_walkthrough_diagnosis.html")
    assert ns["d"].cause == "slip_trend"
