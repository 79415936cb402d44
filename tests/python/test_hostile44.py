"""Issue 44, the fourth hostile round, in Python: a batch of a device or a
FIFO ends at once; Ctrl-C stops a batch running in another thread; a
``Result`` folder is written as ``run --out`` writes its own (never through
a link) and read back only from plain files of its own; a malformed one is
an ``EnginedynError`` naming the file. Runs that could hang run in a
subprocess with a deadline."""

import json
import os
import subprocess
import sys

import pytest

import enginedyn as ed


def _session():
    return ed.Session(ed.Engine.from_toml("data/single.toml"))


# ---------------------------------------------------------------- item 2

BATCH_OF_DEVICES = """
import os, sys, time
import enginedyn as ed
s = ed.Session(ed.Engine.from_toml("data/single.toml"))
started = time.perf_counter()
b = s.batch(["/dev/zero", os.environ["FIFO"], "data/single.csv"])
print(time.perf_counter() - started)
for e in b.errors:
    print(e)
"""


def test_batch_of_a_device_and_a_fifo_ends(tmp_path):
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    env = dict(os.environ, FIFO=str(fifo))
    p = subprocess.run([sys.executable, "-c", BATCH_OF_DEVICES], capture_output=True, text=True, env=env, timeout=60)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    assert float(lines[0]) < 5, p.stdout
    assert "not a regular file" in lines[1] and "not a regular file" in lines[2], p.stdout
    assert lines[3] == "None", p.stdout


# ---------------------------------------------------------------- item 3

BATCH_IN_A_THREAD = """
import os, signal, sys, threading, time
import enginedyn as ed
sys.path.insert(0, "tests/python")
from test_habits import copies_in
s = ed.Session(ed.Engine.from_toml("data/single.toml"))
files = copies_in(os.environ["DIR"], 3000)
outcome = {}
def work():
    try:
        s.batch(files, jobs=1)
        outcome["how"] = "finished"
    except KeyboardInterrupt:
        outcome["how"] = "interrupted"
    outcome["at"] = time.perf_counter()
t = threading.Thread(target=work)
t.start()
time.sleep(0.5)
try:
    sent = time.perf_counter()
    os.kill(os.getpid(), signal.SIGINT)
    while t.is_alive():
        t.join(0.05)
    print("no KeyboardInterrupt in the main thread")
except KeyboardInterrupt:
    pass
t.join()
print(outcome["how"], outcome["at"] - sent)
"""


def test_ctrl_c_stops_a_batch_running_in_a_thread(tmp_path):
    env = dict(os.environ, DIR=str(tmp_path))
    p = subprocess.run([sys.executable, "-c", BATCH_IN_A_THREAD], capture_output=True, text=True, env=env, timeout=600)
    assert p.returncode == 0, p.stderr
    how, seconds = p.stdout.split()
    assert how == "interrupted", p.stdout
    assert float(seconds) < 1.0, p.stdout


# ---------------------------------------------------------------- items 5-7


@pytest.fixture(scope="module")
def result():
    return _session().analyse()


def test_to_folder_never_writes_through_a_link(tmp_path, result):
    outside = tmp_path / "mine.json"
    outside.write_text("the user's own")
    folder = tmp_path / "run1"
    folder.mkdir()
    (folder / "summary.json").symlink_to(outside)
    with pytest.raises(ed.UsageError, match="summary.json: a symbolic link is in the way"):
        result.to_folder(folder)
    assert outside.read_text() == "the user's own"
    assert sorted(os.listdir(folder)) == ["summary.json"]


def test_to_folder_writes_as_run_out_does(tmp_path, result, cli):
    folder = tmp_path / "run1"
    result.to_folder(folder)
    names = sorted(os.listdir(folder))
    # The output folders' record, and no staging left: the one writer.
    assert ".enginedyn-manifest" in names, names
    assert not [n for n in names if n.startswith(".enginedyn-staging")]
    manifest = (folder / ".enginedyn-manifest").read_text()
    assert "enginedyn-result.json" in manifest and "summary.json" in manifest
    back = ed.Result.load(folder)
    assert back.summary == result.summary
    assert back.files() == result.files()


def _saved(folder):
    return json.loads((folder / "enginedyn-result.json").read_text())


def _save(folder, state):
    (folder / "enginedyn-result.json").write_text(json.dumps(state))


def test_load_names_only_plain_files_of_its_own(tmp_path, result):
    mine = tmp_path / "mine"
    folder = mine / "run1"
    result.to_folder(folder)
    notes = mine / "notes.txt"
    notes.write_text("my notes")
    state = _saved(folder)
    for bad in ["../notes.txt", str(notes), ".enginedyn-manifest", "sub/summary.json"]:
        _save(folder, dict(state, files=state["files"] + [bad]))
        with pytest.raises(ed.EnginedynError, match="not a plain file name inside the folder") as e:
            ed.Result.load(folder)
        assert e.value.path == str(folder / bad), e.value
    _save(folder, state)
    ed.Result.load(folder).to_folder(folder)
    assert notes.read_text() == "my notes"


def test_load_refuses_a_linked_file(tmp_path, result):
    folder = tmp_path / "run1"
    result.to_folder(folder)
    other = tmp_path / "other.json"
    other.write_bytes((folder / "summary.json").read_bytes().replace(b"imep_bar", b"IMEP_BAR"))
    (folder / "summary.json").unlink()
    (folder / "summary.json").symlink_to(other)
    with pytest.raises(ed.EnginedynError, match="summary.json: .*a symbolic link"):
        ed.Result.load(folder)
    # A summary.json changed since: its bytes are not the saved summary's.
    (folder / "summary.json").unlink()
    (folder / "summary.json").write_bytes(other.read_bytes())
    with pytest.raises(ed.EnginedynError, match="summary.json: not a result Result.to_folder wrote"):
        ed.Result.load(folder)


@pytest.mark.parametrize(
    "edit",
    [
        lambda s: "{not json",
        lambda s: "[1, 2]",
        lambda s: json.dumps({k: v for k, v in s.items() if k != "files"}),
        lambda s: json.dumps(dict(s, files="summary.json")),
        lambda s: json.dumps(dict(s, files=[1])),
        lambda s: json.dumps(dict(s, summary_json=None)),
        lambda s: json.dumps(dict(s, curves={"angle_deg": "x"})),
        lambda s: json.dumps(dict(s, cycles={"imep_bar": {"dtype": "nonsense", "values": [1]}})),
    ],
    ids=["not-json", "not-object", "no-files", "files-string", "files-int", "summary-null", "curves", "cycles"],
)
def test_load_of_a_malformed_folder_names_the_file(tmp_path, result, edit):
    folder = tmp_path / "run1"
    result.to_folder(folder)
    saved = folder / "enginedyn-result.json"
    saved.write_text(edit(_saved(folder)))
    with pytest.raises(ed.EnginedynError, match="enginedyn-result.json: not a result Result.to_folder wrote") as e:
        ed.Result.load(folder)
    assert e.value.path == str(saved)
