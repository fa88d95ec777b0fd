"""docs/run_pages.py's staleness check, which the Sphinx build uses to run the page scripts it
needs (the README's docs command in a fresh clone): a page is stale until it passed, and again
when a file of its folder changes."""

import importlib.util
from pathlib import Path

DOCS = Path(__file__).parents[1] / "docs"


def _run_pages():
    spec = importlib.util.spec_from_file_location("run_pages", DOCS / "run_pages.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_a_page_is_stale_until_it_passes_and_when_its_folder_changes(tmp_path, monkeypatch):
    rp = _run_pages()
    monkeypatch.setattr(rp, "OUT", tmp_path / "_pages")
    page = tmp_path / "howto" / "demo"
    page.mkdir(parents=True)
    script = page / "demo.sh"
    script.write_text("echo hello > out.json\n")
    assert rp.stale("demo", script)  # never run
    assert rp.run("demo", script)
    assert (tmp_path / "_pages" / "demo" / "out.json").read_text() == "hello\n"
    assert not rp.stale("demo", script)
    (page / "notes.txt").write_text("a new file in the page's folder")
    assert rp.stale("demo", script)


def test_a_failing_page_stays_stale(tmp_path, monkeypatch):
    rp = _run_pages()
    monkeypatch.setattr(rp, "OUT", tmp_path / "_pages")
    page = tmp_path / "tutorials" / "broken"
    page.mkdir(parents=True)
    script = page / "broken.sh"
    script.write_text("exit 3\n")
    assert not rp.run("broken", script)
    assert rp.stale("broken", script)
    assert not (tmp_path / "_pages" / "broken" / "passed").exists()
