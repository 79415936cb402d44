"""The package's own contract: options checked by the library, typed
errors, pickling, a batch that finishes, and the GIL released."""

import pickle
import subprocess
import threading
import time

import pytest

import enginedyn as ed


def test_options_out_of_bounds_name_the_argument():
    with pytest.raises(ed.UsageError, match="step_deg"):
        ed.Method(step_deg=20)
    with pytest.raises(ed.UsageError, match="kinematics.*exact, series2"):
        ed.Method(kinematics="series3")
    with pytest.raises(ed.UsageError, match="peg_bar"):
        ed.Reader(peg_bar=-1.0)
    with pytest.raises(ed.UsageError, match="rpm"):
        ed.Reader(rpm=0.0)
    # Reader has a real signature: a typo is Python's TypeError (and mypy's).
    with pytest.raises(TypeError, match="unexpected keyword argument 'tdc'"):
        ed.Reader(tdc=3.0)  # type: ignore[call-arg]
    with pytest.raises(ed.UsageError, match="step must divide"):
        ed.Session(ed.Engine.bundled(), method=ed.Method(step_deg=0.7))
    assert issubclass(ed.UsageError, ed.EnginedynError)


def test_errors_are_typed_with_where():
    s = ed.Session(ed.Engine.from_toml("data/single.toml"))
    with pytest.raises(ed.DiagramError) as e:
        s.analyse("tests/fixtures/measured/cycle_fraction.csv")
    assert (e.value.path, e.value.line) == ("tests/fixtures/measured/cycle_fraction.csv", 283)
    with pytest.raises(FileNotFoundError):
        ed.Engine.from_toml("no/such/engine.toml")
    with pytest.raises(OSError):
        s.analyse("no/such/diagram.csv")
    with pytest.raises(ed.EngineFileError) as e:
        ed.Engine.from_str(open("data/single.toml").read().replace("bore_mm = 68", "bore_mm = -68"))
    assert e.value.key == "bore_mm"


def test_a_session_pickles_and_gives_the_same_numbers():
    s = ed.Session(
        ed.Engine.from_toml("data/single.toml"),
        method=ed.Method(step_deg=0.5, kinematics="series2"),
        reader=ed.Reader(max_gap_deg=20),
    )
    t = pickle.loads(pickle.dumps(s))
    assert (t.method, t.reader) == (s.method, s.reader)
    assert t.analyse("data/single.csv").summary == s.analyse("data/single.csv").summary
    b = pickle.loads(pickle.dumps(ed.Session(ed.Engine.bundled("v8_crossplane"))))
    assert b.engine.name == ed.Engine.bundled("v8_crossplane").name


def test_a_batch_with_bad_files_finishes():
    s = ed.Session(ed.Engine.from_toml("data/single.toml"))
    files = ["data/single.csv", "no/such.csv", "tests/fixtures/measured/image_renamed.csv", "data/vaz2108.csv"]
    b = s.batch(files, jobs=2)
    assert b.files == files
    assert b.errors[0] is None and b.errors[3] is None
    assert "cannot open" in b.errors[1] and "not a text file" in b.errors[2]
    one = s.analyse("data/single.csv").summary
    assert b.summaries()[0]["imep_bar"] == one["imep_bar"]
    df = b.to_pandas()
    assert list(df["file"]) == files and df["error"].isna().tolist() == [True, False, False, True]


def test_the_gil_is_released_while_computing(tmp_path):
    """Python code runs on another thread while a batch computes."""
    s = ed.Session(ed.Engine.from_toml("data/single.toml"))
    text = open("data/single.csv").read()
    files = []
    for k in range(300):
        files.append(tmp_path / f"c{k}.csv")
        files[-1].write_text(text)
    ticks = []
    done = threading.Event()

    def tick():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    t = threading.Thread(target=tick)
    t.start()
    started = time.perf_counter()
    s.batch(files, jobs=1)
    elapsed = time.perf_counter() - started
    done.set()
    t.join()
    during = [x for x in ticks if started < x < started + elapsed]
    # Held GIL: the ticker would not run at all during the call.
    assert len(during) > 10, (elapsed, len(during))


def test_results_carry_curves_harmonics_and_charts():
    r = ed.Session(ed.Engine.bundled("vaz2108")).analyse()
    c = r.curves
    assert len(c["crank_deg"]) == 7200 and c["crank_deg"][1] == 0.1
    # The torque is the pressure's: mean torque over the cycle.
    assert abs(c["torque_engine_nm"].mean() - r.summary["indicated_mean_torque_nm"]) < 1e-6 * abs(
        r.summary["indicated_mean_torque_nm"]
    )
    assert list(r.harmonics["order"][:3]) == [0.0, 0.5, 1.0]
    svg = r.svg("torque")
    assert svg.startswith("<svg") or "<svg" in svg[:200]
    with pytest.raises(ed.UsageError, match="no chart"):
        r.svg("nope")
    assert "<table>" in r._repr_html_()
    names = [n for n, _ in r.files()]
    assert {"summary.json", "curves.csv", "report.html"} <= set(names)


def test_torsion_gives_the_clis_files(cli, tmp_path):
    out = tmp_path / "t"
    subprocess.run(
        [cli, "torsion", "--engine", "data/i6_diesel.toml", "--rpm", "600:2600:100", "--out", str(out)],
        check=True,
        capture_output=True,
    )
    t = ed.Session(ed.Engine.from_toml("data/i6_diesel.toml")).torsion(rpm=(600, 2600, 100))
    assert t.json_text == (out / "torsion.json").read_text()
    assert t.torsion_csv == (out / "torsion.csv").read_text()
    assert t.modes_csv == (out / "modes.csv").read_text()
    assert t.svg("campbell") == (out / "campbell.svg").read_text()
    r = t.response
    assert r["rpm"][0] == 600.0 and r["rpm"][-1] == 2600.0 and len(r["rpm"]) == 21
    assert t.modes["frequency_hz"][0] > 0
    with pytest.raises(ed.UsageError):
        ed.Session(ed.Engine.from_toml("data/single.toml")).torsion()


def test_a_results_tables_are_the_campaigns():
    pa = pytest.importorskip("pyarrow")
    s = ed.Session(ed.Engine.from_toml("data/single.toml"))
    r = s.analyse("tests/fixtures/measured/dropout_20cycles.csv")
    c = r.cycles
    assert len(c["cycle"]) == 20 and int((~c["used"]).sum()) == 2
    assert all(reason for reason, used in zip(c["skip_reason"], c["used"]) if not used)
    used = c["imep_bar"][c["used"]]
    assert abs(used.mean() - r.summary["imep_bar"]) <= 1e-9 * r.summary["imep_bar"]
    t = r.to_arrow()
    b = s.batch(["tests/fixtures/measured/dropout_20cycles.csv"], jobs=1).to_arrow()
    assert t.num_rows == 1 and t.schema == b.schema
    assert t.column("imep_bar")[0].as_py() == r.summary["imep_bar"]
    assert r.to_pandas()["cycles_skipped"][0] == 2


def test_an_engine_file_is_a_regular_file_of_at_most_a_mebibyte(tmp_path):
    # /dev/zero never ends: refused before it is read, as the CLI refuses it.
    t = time.perf_counter()
    with pytest.raises((ed.EnginedynError, OSError), match="regular file"):
        ed.Engine.from_toml("/dev/zero")
    assert time.perf_counter() - t < 2.0
    big = tmp_path / "big.toml"
    big.write_text("# " + "x" * (1 << 20) + "\n")
    with pytest.raises((ed.EnginedynError, OSError), match="MiB"):
        ed.Engine.from_toml(str(big))
