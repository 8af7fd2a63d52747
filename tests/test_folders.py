"""course_dynamics/output/folders.py: a command replaces only its own files; hostile manifests authorise nothing."""
from __future__ import annotations

import pytest

from course_dynamics import InputError
from course_dynamics.output.folders import (
    MANIFEST,
    MANIFEST_MAX_BYTES,
    check_folder,
    write_folder,
)


def manifest_of(folder):
    import json

    return json.loads((folder / MANIFEST).read_text())["files"]


def test_an_output_folder_replaces_only_its_own_files(tmp_path):
    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    written = write_folder(out, {"index.html": "<p>1</p>", "figures/a.svg": b"<svg/>"}, "report")
    assert written == [out / "index.html", out / "figures" / "a.svg"]
    assert {name: entry["command"] for name, entry in manifest_of(out).items()} == {"index.html": "report",
                                                                                     "figures/a.svg": "report"}
    write_folder(out, {"index.html": "<p>2</p>", "figures/a.svg": "<svg>2</svg>"}, "report")  # ours, unchanged
    assert (out / "index.html").read_text() == "<p>2</p>" and (out / "notes.txt").read_text() == "mine"
    assert sorted(p.name for p in out.iterdir()) == [MANIFEST, "figures", "index.html", "notes.txt"]


def test_files_an_earlier_run_wrote_are_kept_and_stay_ours(tmp_path):
    write_folder(tmp_path, {"a.md": "a", "b.md": "b"}, "grade")
    write_folder(tmp_path, {"a.md": "a2"}, "grade")
    assert (tmp_path / "b.md").read_text() == "b" and set(manifest_of(tmp_path)) == {"a.md", "b.md"}
    write_folder(tmp_path, {"b.md": "b2"}, "grade")
    assert (tmp_path / "b.md").read_text() == "b2"
    (tmp_path / "a.md").unlink()
    write_folder(tmp_path, {"b.md": "b3"}, "grade")
    assert set(manifest_of(tmp_path)) == {"b.md"}  # a file gone is no longer listed


@pytest.mark.parametrize("prepare, fragment", [
    (lambda out: (out / "index.html").write_text("a page of my own"), "index.html: exists and was not written by "
                                                                         "course-dynamics"),
    (lambda out: (write_folder(out, {"index.html": "x"}, "report"), (out / "index.html").write_text("edited")),
     "index.html: was changed since course-dynamics report wrote it"),
    (lambda out: write_folder(out, {"index.html": "x"}, "publish-notebooks"),
     "index.html: was written by course-dynamics publish-notebooks, not report"),
    (lambda out: (out / "index.html").mkdir(), "index.html: is a directory, not a file course-dynamics wrote"),
    (lambda out: (write_folder(out, {"index.html": "x"}, "report"), (out / "index.html").unlink(),
                  (out / "index.html").symlink_to(out.parent / "victim")),
     "index.html: is a symbolic link, not a file course-dynamics wrote"),
    (lambda out: (out / "figures").symlink_to(out.parent / "elsewhere"), "figures: is not a plain folder"),
    (lambda out: (out / "figures").write_text("a file"), "figures: is not a plain folder"),
])
def test_an_output_folder_refuses_what_it_did_not_write_before_writing_anything(tmp_path, prepare, fragment):
    out, elsewhere = tmp_path / "out", tmp_path / "elsewhere"
    out.mkdir()
    elsewhere.mkdir()
    (tmp_path / "victim").write_text("precious")
    prepare(out)
    before = {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file() and not p.is_symlink()}
    with pytest.raises(InputError) as caught:
        write_folder(out, {"new.md": "n", "index.html": "<p>new</p>", "figures/a.svg": "<svg/>"}, "report")
    assert fragment in str(caught.value) and "nothing was written" in str(caught.value), caught.value
    assert {p: p.read_bytes() for p in tmp_path.rglob("*") if p.is_file() and not p.is_symlink()} == before
    assert not (out / "new.md").exists() and list(elsewhere.iterdir()) == []


HOSTILE_MANIFESTS = {
    "not JSON": b"{\"files\": ",
    "not UTF-8": b"\xff\xfe\x00",
    "a list": b"[]",
    "no version": b'{"files": {"index.html": {"command": "report", "versions": []}}}',
    "another format": b'{"course-dynamics": 2, "files": {}}',
    "files as a list": b'{"course-dynamics": 1, "files": ["index.html"]}',
    "a bad hash": b'{"course-dynamics": 1, "files": {"index.html": {"command": "report", "versions": '
                  b'[{"bytes": 1, "sha256": "zz"}]}}}',
    "deeply nested": b"[" * 100_000 + b"]" * 100_000,
}


def hostile_entry(name: str, content: bytes) -> bytes:
    import hashlib
    import json

    version = {"bytes": len(content), "sha256": hashlib.sha256(content).hexdigest()}
    return json.dumps({"course-dynamics": 1, "files": {name: {"command": "report", "versions": [version]}}}).encode()


@pytest.mark.parametrize("kind", list(HOSTILE_MANIFESTS) + ["names ../victim", "names an absolute path", "a link",
                                                            "too large"])
def test_a_hostile_manifest_is_refused_and_authorises_nothing(tmp_path, kind):
    out = tmp_path / "out"
    out.mkdir()
    victim = tmp_path / "victim"
    victim.write_bytes(b"precious")
    manifest = out / MANIFEST
    if kind == "names ../victim":
        manifest.write_bytes(hostile_entry("../victim", b"precious"))
    elif kind == "names an absolute path":
        manifest.write_bytes(hostile_entry(str(victim), b"precious"))
    elif kind == "a link":
        real = tmp_path / "real.json"
        real.write_bytes(hostile_entry("index.html", b"mine"))
        manifest.symlink_to(real)
    elif kind == "too large":
        with open(manifest, "wb") as handle:
            handle.truncate(MANIFEST_MAX_BYTES + 1)
    else:
        manifest.write_bytes(HOSTILE_MANIFESTS[kind])
    (out / "index.html").write_bytes(b"mine")
    with pytest.raises(InputError) as caught:
        write_folder(out, {"index.html": "x"}, "report")
    assert "nothing was written" in str(caught.value), caught.value
    assert victim.read_bytes() == b"precious" and (out / "index.html").read_bytes() == b"mine"


def test_a_run_interrupted_half_way_leaves_files_the_next_run_may_replace(tmp_path, monkeypatch):
    write_folder(tmp_path, {"a.md": "a1", "b.md": "b1"}, "grade")
    from course_dynamics.output import folders

    real = folders.whole_file

    def interrupted(path, *args, **kwargs):
        if path.name == "b.md":
            raise KeyboardInterrupt
        return real(path, *args, **kwargs)

    monkeypatch.setattr(folders, "whole_file", interrupted)
    with pytest.raises(KeyboardInterrupt):
        write_folder(tmp_path, {"a.md": "a2", "b.md": "b2"}, "grade")
    monkeypatch.setattr(folders, "whole_file", real)
    assert (tmp_path / "a.md").read_text() == "a2" and (tmp_path / "b.md").read_text() == "b1"
    write_folder(tmp_path, {"a.md": "a3", "b.md": "b3"}, "grade")  # both recognised: the old b, the new a
    assert (tmp_path / "a.md").read_text() == "a3" and (tmp_path / "b.md").read_text() == "b3"


@pytest.mark.parametrize("name", ["../x", "/etc/x", "a/../../x", "", "a//b", "./a", MANIFEST])
def test_output_folder_names_stay_inside(tmp_path, name):
    with pytest.raises(InputError):
        write_folder(tmp_path / "out", {name: "x"}, "report")
    assert not (tmp_path / "out").exists() and not (tmp_path / "x").exists()


def test_check_folder_fails_early_and_writes_nothing(tmp_path):
    check_folder(tmp_path / "new" / "site", ["index.html"], "report")  # a folder to be made: fine
    assert not (tmp_path / "new").exists()
    (tmp_path / "index.html").write_text("mine")
    with pytest.raises(InputError, match="index.html: exists and was not written by course-dynamics"):
        check_folder(tmp_path, ["index.html", "report.md"], "report")
    (tmp_path / "file").write_text("x")
    with pytest.raises(InputError, match="Not a directory"):
        check_folder(tmp_path / "file" / "site", ["index.html"], "report")
