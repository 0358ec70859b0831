"""Issue 12.4: replacing a report keeps the files of the folder that the report does not own."""

from __future__ import annotations

import os

from designer.report.writer import _replace


def _report(folder, marker: str) -> None:
    folder.mkdir()
    (folder / "figures").mkdir()
    (folder / "figures" / "front.png").write_text(marker)
    for name in ("index.html", "report.md", "front.csv", "front.json", "checks.json"):
        (folder / name).write_text(marker)


def test_replace_keeps_explore_files_and_user_files(tmp_path):
    """explore.csv / explore.json (written by `designer explore`) and a user's notes survive a report
    replace; the report's own files and figures are the new ones; no moved-aside folder is left."""
    target, tmp = tmp_path / "indoor-manual", tmp_path / ".indoor-manual.tmp-x"
    _report(target, "old")
    (target / "explore.csv").write_text("trail,diameter\n0.05,0.2\n")
    (target / "explore.json").write_text('{"trials": 500}')
    (target / "notes").mkdir()
    (target / "notes" / "why.txt").write_text("mine")
    (target / "figures" / "stale.png").write_text("old")  # inside the report's own folder: replaced whole
    _report(tmp, "new")
    _replace(tmp, target)
    assert (target / "explore.csv").read_text() == "trail,diameter\n0.05,0.2\n"
    assert (target / "explore.json").read_text() == '{"trials": 500}'
    assert (target / "notes" / "why.txt").read_text() == "mine"
    assert (target / "index.html").read_text() == "new" and (target / "front.json").read_text() == "new"
    assert sorted(p.name for p in (target / "figures").iterdir()) == ["front.png"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["indoor-manual"]


def test_replace_failure_keeps_old_folder_whole(tmp_path, monkeypatch):
    """If the final rename fails, the old folder (with explore.csv) is back in place, untouched."""
    target, tmp = tmp_path / "r", tmp_path / ".r.tmp-x"
    _report(target, "old")
    (target / "explore.csv").write_text("keep")
    _report(tmp, "new")
    real_rename = os.rename

    def failing(src, dst, *a, **k):
        if str(src) == str(tmp):
            raise PermissionError(13, "Permission denied")
        return real_rename(src, dst, *a, **k)

    monkeypatch.setattr("pathlib.os.rename", failing)
    try:
        _replace(tmp, target)
    except PermissionError:
        pass
    monkeypatch.undo()
    assert (target / "explore.csv").read_text() == "keep" and (target / "index.html").read_text() == "old"
