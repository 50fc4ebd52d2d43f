"""README.md's result blocks are the render of the landed CSVs under docs/results/ and of the
systems' own records (:mod:`terrabench.report.readme`), so the README's numbers cannot drift."""

from __future__ import annotations

import csv
import shutil
from pathlib import Path

import pytest

from terrabench.report import readme as rd

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"


@pytest.fixture(scope="module")
def fresh() -> dict[str, str]:
    try:
        return rd.render(ROOT)
    except rd.MissingSource as exc:  # only when a report's CSV is not in this checkout
        pytest.skip(f"a CSV the README is rendered from is absent: {exc}")


def test_readme_blocks_are_the_render_of_the_csvs(fresh):
    left = rd.problems(README.read_text(), fresh)
    assert not left, "\n\n".join(left)


def test_render_is_deterministic(fresh):
    assert rd.render(ROOT) == fresh


def test_every_block_names_its_sources(fresh):
    for name, text in fresh.items():
        if name in ("systems-table", "envs"):  # from the registry, not a CSV
            continue
        assert "Source: `docs/results/" in text, name


def test_check_names_the_block_and_the_command(fresh):
    text = README.read_text()
    block = rd.found_blocks(text)["mrs-cwc-table"]
    tampered = text.replace(block, block.replace("| MRS-CWC + TDT |", "| MRS-CWC + TDT (edited) |", 1))
    assert tampered != text
    left = rd.problems(tampered, fresh)
    assert len(left) == 1 and "'mrs-cwc-table'" in left[0] and rd.WRITE_COMMAND in left[0]
    assert rd.rewrite(tampered, fresh) == text  # --write restores it


def test_a_missing_block_is_reported(fresh):
    text = README.read_text()
    without = text.replace(rd.found_blocks(text)["soil-cmu"], "")
    left = rd.problems(without, fresh)
    assert any("no block 'soil-cmu'" in p for p in left), left


def test_missing_required_csv_fails_loudly(tmp_path, capsys):
    (tmp_path / "docs" / "results").mkdir(parents=True)
    (tmp_path / "README.md").write_text("# x\n")
    with pytest.raises(rd.MissingSource, match="docs/results/mrs-cwc/table_A.csv"):
        rd.block_mrs_table(rd.Sources(tmp_path))
    assert rd.main(["--check", "--root", str(tmp_path)]) == 2
    assert "is missing" in capsys.readouterr().err


def test_absent_optional_columns_render_as_dashes(tmp_path):
    src = ROOT / "docs" / "results" / "srwmr" / "tasks.csv"
    if not src.is_file():
        pytest.skip(f"{src.relative_to(ROOT)} is absent")
    with src.open(newline="") as f:
        rows = list(csv.DictReader(f))
    keep = [c for c in rows[0] if c not in ("body slip", "paper")]
    out = tmp_path / "docs" / "results" / "srwmr"
    out.mkdir(parents=True)
    with (out / "tasks.csv").open("w", newline="") as f:
        w = csv.DictWriter(f, keep, extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    body = rd.block_srwmr_tasks(rd.Sources(tmp_path)).body
    assert "| `t1-loose` | WRM | success | - |" in body


def test_no_seeds_report_renders_a_note(tmp_path):
    shutil.copytree(ROOT / "docs" / "results" / "mrs-cwc", tmp_path / "docs" / "results" / "mrs-cwc")
    assert "No report with several seeds" in rd.block_mrs_seeds(rd.Sources(tmp_path)).body


def test_system_table_agrees_with_terrabench_list():
    """`terrabench list` prints the registry records' summaries; they are the systems' own, and
    every system says what is built."""
    from terrabench.catalog import populate, system

    reg = populate()
    for sid in reg.ids("system"):
        sysobj = system(sid)
        assert reg.get("system", sid).summary == sysobj.summary, sid
        assert sysobj.status.strip(), f"{sid} has no status line (System.status)"
    srwmr = system("srwmr")
    assert "not yet" not in srwmr.status and "SWLM" in srwmr.status
    assert len(srwmr.instances("tasks")) > 7
