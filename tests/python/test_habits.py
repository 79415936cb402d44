"""Python's habits (issue 37, part C): results and exceptions cross
processes, Ctrl-C, warnings apart from notes, arrays checked like files,
messages in keywords, a native feel."""

import inspect
import json
import multiprocessing
import os
import pickle
import subprocess
import sys
import textwrap
import warnings

import numpy as np
import pytest

import enginedyn as ed

SINGLE = "data/single.toml"
WARNED = "tests/fixtures/measured/digitised_gap_exhaust.csv"
BAD = "tests/fixtures/measured/cycle_fraction.csv"


def session(**reader):
    return ed.Session(ed.Engine.from_toml(SINGLE), reader=ed.Reader(**reader))


def same_columns(a, b):
    assert a.keys() == b.keys()
    for k in a:
        if isinstance(a[k], list):
            assert a[k] == b[k], k
        else:
            assert a[k].dtype == b[k].dtype, k
            assert np.array_equal(a[k], b[k], equal_nan=a[k].dtype.kind == "f"), k


def same_result(r, t):
    assert t.summary_json() == r.summary_json()
    assert (t.notes, t.warnings) == (r.notes, r.warnings)
    same_columns(r.curves, t.curves)
    same_columns(r.harmonics, t.harmonics)
    same_columns(r.cycles, t.cycles)
    assert t.charts() == r.charts() and t.svg("torque") == r.svg("torque")
    assert t.files() == r.files()
    assert t.to_arrow().equals(r.to_arrow())


# ---------------------------------------------------------------- item 11


def test_a_result_and_a_batch_pickle():
    s = session()
    r = s.analyse("data/single.csv")
    same_result(r, pickle.loads(pickle.dumps(r)))
    b = s.batch(["data/single.csv", "no/such.csv"], jobs=1)
    c = pickle.loads(pickle.dumps(b))
    assert (c.files, c.errors, c.summaries()) == (b.files, b.errors, b.summaries())
    assert c.to_arrow().equals(b.to_arrow()) and c.cycles_arrow().equals(b.cycles_arrow())
    with pytest.raises(ed.UsageError, match="from the batch that ran them"):
        c.write_parquet("unused")


def test_exceptions_pickle_as_the_packages_classes():
    with pytest.raises(ed.DiagramError) as e:
        session().analyse(BAD)
    assert type(e.value).__module__ == "enginedyn"
    back = pickle.loads(pickle.dumps(e.value))
    assert type(back) is ed.DiagramError
    assert (back.path, back.line, back.column) == (BAD, 283, e.value.column)
    assert str(back) == str(e.value)
    with pytest.raises(ed.EngineFileError) as f:
        ed.Engine.from_str(open(SINGLE).read().replace("bore_mm = 68", "bore_mm = -68"))
    back = pickle.loads(pickle.dumps(f.value))
    assert type(back) is ed.EngineFileError and back.key == "bore_mm"


def test_pool_map_returns_results_and_raises_the_packages_errors():
    s = session()
    ctx = multiprocessing.get_context("spawn")
    with ctx.Pool(2) as pool:
        got = pool.map(s.analyse, ["data/single.csv", "data/single.csv"])
        assert [r.summary for r in got] == [s.analyse("data/single.csv").summary] * 2
        with pytest.raises(ed.DiagramError) as e:
            pool.map(s.analyse, [BAD])
    assert e.value.line == 283


def test_dask_client_map_and_a_futures_error():
    distributed = pytest.importorskip("distributed")
    s = session()
    with distributed.Client(
        distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None)
    ) as client:
        futures = client.map(s.analyse, ["data/single.csv", BAD], pure=False)
        assert futures[0].result().summary == s.analyse("data/single.csv").summary
        try:
            futures[1].result()
        except ed.DiagramError as e:
            assert (e.path, e.line) == (BAD, 283)
        else:
            raise AssertionError("no DiagramError")


# ---------------------------------------------------------------- item 12

INTERRUPT = """
import os, signal, sys, threading, time
import numpy as np
import enginedyn as ed
sys.path.insert(0, "tests/python")
s = ed.Session(ed.Engine.from_toml("data/single.toml"))
{setup}
def interrupt():
    global sent
    time.sleep(0.4)
    sent = time.perf_counter()
    os.kill(os.getpid(), signal.SIGINT)
threading.Thread(target=interrupt, daemon=True).start()
started = time.perf_counter()
try:
    {call}
    print("finished", time.perf_counter() - started)
except KeyboardInterrupt:
    print("interrupted", time.perf_counter() - sent)
"""


def long_cycles(n):
    """``n`` cycles of data/single.csv one after another (a long layout)."""
    rows = [r for r in open("data/single.csv").read().splitlines() if r and not r.startswith("#")]
    data = np.array([r.split(",") for r in rows[1:]], dtype=float)
    angle = np.tile(data[:, 0], n)
    p = np.tile(data[:, 1], n)
    cycle = np.repeat(np.arange(1.0, n + 1.0), len(data))
    return angle, p, cycle


def copies_in(folder, n, of="data/single.csv"):
    """`n` files of one diagram in `folder` (one file named n times is one
    row)."""
    import shutil

    out = []
    for k in range(n):
        p = os.path.join(folder, f"copy{k}.csv")
        shutil.copyfile(of, p)
        out.append(p)
    return out


def write_long(path, n):
    rows = [r for r in open("data/single.csv").read().splitlines() if r and not r.startswith("#")]
    block = "\n".join(f"{r},CYC" for r in rows[1:]) + "\n"
    with open(path, "w") as f:
        f.write("crank_deg,pressure_bar,cycle\n")
        for c in range(1, n + 1):
            f.write(block.replace("CYC", str(c)))


@pytest.mark.parametrize(
    "setup,call",
    [
        (
            # Distinct files: one file named many times is one row.
            "from test_habits import copies_in; files = copies_in(os.path.dirname(os.environ['BIG']), 4000)",
            "s.batch(files, jobs=1)",
        ),
        (
            "from test_habits import write_long; write_long(os.environ['BIG'], 6000)",
            "s.analyse(os.environ['BIG'])",
        ),
        (
            "from test_habits import long_cycles; a, p, c = long_cycles(12000)",
            "s.analyse_arrays(a, p, cycle=c)",
        ),
    ],
    ids=["batch", "analyse", "analyse_arrays"],
)
def test_ctrl_c_interrupts_within_half_a_second(tmp_path, setup, call):
    script = INTERRUPT.format(setup=setup, call=call)
    env = dict(os.environ, BIG=str(tmp_path / "big.csv"))
    p = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, env=env, timeout=600)
    assert p.returncode == 0, p.stderr
    word, seconds = p.stdout.split()
    assert word == "interrupted", p.stdout
    assert float(seconds) < 0.5, p.stdout


# ---------------------------------------------------------------- item 13


def cli_lines(cli, *args):
    p = subprocess.run([cli, "run", *args, "--json"], capture_output=True, text=True)
    lines = p.stderr.splitlines()
    return (
        [ln[len("note: ") :] for ln in lines if ln.startswith("note: ")],
        [ln[len("warning: ") :] for ln in lines if ln.startswith("warning: ")],
    )


def test_warnings_and_notes_are_the_clis_apart(cli):
    notes, warned = cli_lines(cli, "--engine", SINGLE, "--diagram", WARNED)
    assert warned, "the fixture gives a warning"
    with pytest.warns(ed.EnginedynWarning) as caught:
        r = session().analyse(WARNED)
    assert (r.notes, r.warnings) == (notes, warned)
    assert [str(w.message) for w in caught] == warned
    b = session().batch([WARNED, "data/single.csv"], jobs=1)
    assert b.warnings == [warned, []]
    assert b.notes[0] == notes


def test_python_W_error_stops_on_a_warning():
    code = f"import enginedyn as ed; ed.Session(ed.Engine.from_toml({SINGLE!r})).analyse({WARNED!r}); print('ran')"
    p = subprocess.run([sys.executable, "-W", "error", "-c", code], capture_output=True, text=True)
    assert p.returncode == 1 and "ran" not in p.stdout
    assert "enginedyn.EnginedynWarning" in p.stderr


def test_the_notebook_marks_warnings():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = session().analyse(WARNED)
    html = r._repr_html_()
    for w in r.warnings:
        assert "&#9888; warning: " + w.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;").replace(
            "'", "&#39;"
        ).replace('"', "&quot;") in html


# ---------------------------------------------------------------- item 14


def record():
    rows = [r.split(",") for r in open("tests/fixtures/measured/daq_72khz_tdc.csv").read().splitlines()]
    data = np.array(rows[1:], dtype=float)
    return data[:, 0], data[:, 1], data[:, 2]


def test_a_timedelta64_time_is_seconds():
    s = session(gain_bar_per_v=20.0, peg_bar=0.95)
    t, v, tdc = record()
    want = s.analyse_time_record(t, pressure_v=v, tdc=tdc).summary
    ns = np.round(t * 1e9).astype("timedelta64[ns]")
    got = s.analyse_time_record(ns, pressure_v=v, tdc=tdc).summary
    assert abs(got["imep_bar"] - want["imep_bar"]) < 1e-9 * abs(want["imep_bar"])
    with pytest.raises(TypeError, match=r"^pressure_v=: a timedelta64 array is a time, not a pressure_v$"):
        s.analyse_time_record(t, pressure_v=ns, tdc=tdc)


def test_a_masked_array_is_refused_with_the_way_to_fill_it():
    s = session()
    a = np.arange(0.0, 720.0, 0.5)
    p = np.ma.masked_less(np.full_like(a, 2.0), 0)
    with pytest.raises(ValueError) as e:
        s.analyse_arrays(a, p)
    assert str(e.value) == (
        "pressure_bar=: a masked array (its mask would be lost): fill it, e.g. pressure_bar.filled(np.nan), "
        "and drop the masked samples from every array alike, or give the samples' cycle= so that a "
        "dropout's cycle is left out"
    )


# ---------------------------------------------------------------- item 15


def test_a_2d_pressure_is_one_row_a_cylinder(cli, tmp_path):
    """Four cylinders as arrays give the CLI's four per-cylinder files.
    The arrays share one TDC pulse, so the peaks decide each trace's axis
    (here every cylinder the same trace: each on its own) and a note says
    so; four files each have their own pulse, and no such note."""
    t, v, tdc = record()
    path = tmp_path / "rec.csv"
    path.write_text(open("tests/fixtures/measured/daq_72khz_tdc.csv").read())
    flags = ["--gain", "20", "--peg-bar", "0.95", "--no-compression-check"]
    p = subprocess.run(
        [cli, "run", "--engine", "data/vaz2108.toml", *sum((["--diagram", str(path)] for _ in range(4)), []), *flags, "--json"],
        capture_output=True,
        text=True,
    )
    assert p.returncode == 0, p.stderr
    want = json.loads(p.stdout)
    s = ed.Session(
        ed.Engine.from_toml("data/vaz2108.toml"),
        reader=ed.Reader(gain_bar_per_v=20.0, peg_bar=0.95, compression_check=False),
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        got = s.analyse_time_record(t, pressure_v=np.vstack([v] * 4), tdc=tdc).summary
    got.pop("inputs"), want.pop("inputs")
    axis = [n for n in got["notes"] if n not in want["notes"]]
    assert len(axis) == 1 and axis[0].startswith("cylinder traces each on its own crank angle"), axis
    got["notes"].remove(axis[0])
    assert got == want


def test_an_encoder_array_is_the_files_encoder_column():
    path = "tests/fixtures/measured/daq_100khz_encoder_360.csv"
    rows = [r.split(",") for r in open(path).read().splitlines()]
    data = np.array(rows[1:], dtype=float)
    s = session(encoder_ppr=360)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        want = s.analyse(path).summary
        got = s.analyse_time_record(data[:, 0], pressure_bar=data[:, 1], tdc=data[:, 2], encoder=data[:, 3]).summary
    want.pop("inputs"), got.pop("inputs")
    assert got == want


# ---------------------------------------------------------------- item 16


def test_messages_name_keywords_not_flags():
    with pytest.raises(ed.UsageError) as e:
        ed.Session(ed.Engine.bundled(), method=ed.Method(step_deg=0.7))
    assert str(e.value) == "step_deg=0.7: the step must divide the 720° cycle (0.1, 0.2, 0.25, 0.5, 1, …)"
    text = "\n".join(ln for ln in open(SINGLE).read().splitlines() if not ln.startswith("diagram"))
    with pytest.raises(ed.UsageError) as e:
        ed.Session(ed.Engine.from_str(text)).analyse()
    assert str(e.value) == "no indicator diagram: give diagram= or `diagram =` in the engine file"
    assert ed._native.in_keywords("--parts 3: 4 parts found") == "parts=3: 4 parts found"


def test_a_missing_file_is_file_not_found_with_its_path():
    with pytest.raises(FileNotFoundError) as e:
        session().analyse("no/such/diagram.csv")
    assert e.value.filename == "no/such/diagram.csv" and e.value.errno == 2
    with pytest.raises(FileNotFoundError) as e:
        ed.Engine.from_toml("no/such/engine.toml")
    assert e.value.filename == "no/such/engine.toml"


def test_jobs_minus_one_is_every_core_and_one_path_is_a_type_error(tmp_path):
    s = session()
    three = copies_in(str(tmp_path), 3)
    assert s.batch(three, jobs=-1).errors == [None] * 3
    assert s.batch(three, jobs=-2).errors == [None] * 3
    with pytest.raises(ed.UsageError, match=r"^jobs=-1000: this machine has \d+ cores"):
        s.batch(["data/single.csv"], jobs=-1000)
    with pytest.raises(TypeError) as e:
        s.batch("data/single.csv")
    assert str(e.value) == (
        "paths=: a list of files is needed, not one path ('data/single.csv'): "
        "batch([path]), or analyse(path) for one file"
    )


def test_a_nan_suggests_dropping_the_rows_or_cycle():
    a = np.arange(0.0, 720.0, 0.5)
    p = np.full_like(a, 2.0)
    p[7] = np.nan
    with pytest.raises(ed.DiagramError) as e:
        session().analyse_arrays(a, p)
    assert str(e.value) == (
        "arrays: line 8, column 2: NaN is not a finite number: drop the samples where a value is missing "
        "(from every array alike: a gap up to max_gap_deg is bridged), or give each sample's cycle (cycle=) "
        "so that a dropout's cycle is left out"
    )


# ---------------------------------------------------------------- item 17


def test_io_and_dask_load_on_first_use_and_dir_lists_the_api():
    code = textwrap.dedent(
        """
        import sys, enginedyn as ed
        assert "enginedyn.io" not in sys.modules and "enginedyn.dask" not in sys.modules
        assert callable(ed.io.read_mdf) and callable(ed.dask.shards)
        print(sorted(dir(ed)))
        """
    )
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    assert eval(p.stdout) == sorted(
        [
            "Batch", "DiagramError", "Engine", "EngineFileError", "EnginedynError", "EnginedynWarning",
            "Method", "Reader", "Result", "Session", "Torsion", "UsageError", "__version__", "dask", "io",
        ]
    )


def test_reader_and_method_have_real_signatures(tmp_path):
    params = inspect.signature(ed.Reader).parameters
    assert list(params)[:3] == ["tdc_deg", "columns", "skip_lines"]
    assert all(p.kind is inspect.Parameter.KEYWORD_ONLY for p in params.values())
    assert "step_deg" in inspect.signature(ed.Method).parameters
    with pytest.raises(TypeError, match="tdc_dge"):
        ed.Reader(tdc_dge=1.0)
    with pytest.raises(AttributeError):
        ed.Reader().tdc_dge
    snippet = tmp_path / "typo.py"
    snippet.write_text("import enginedyn as ed\ned.Reader(tdc_dge=1.0)\ned.Method(stepdeg=0.5)\n")
    # The package being tested, wherever it is imported from.
    env = dict(os.environ, MYPYPATH=os.path.dirname(os.path.dirname(ed.__file__)))
    p = subprocess.run(
        [sys.executable, "-m", "mypy", "--no-incremental", "--config-file", "crates/python/mypy.ini", str(snippet)],
        capture_output=True,
        text=True,
        env=env,
    )
    assert 'Unexpected keyword argument "tdc_dge" for "Reader"' in p.stdout, p.stdout
    assert 'Unexpected keyword argument "stepdeg" for "Method"' in p.stdout, p.stdout


def test_the_notebook_shows_units_and_rounded_figures():
    r = session().analyse("data/single.csv")
    html = r._repr_html_()
    s = r.summary
    assert f"<th style='text-align:left'>IMEP</th><td style='text-align:right'>{s['imep_bar']:,.3f}</td><td>bar</td>" in html
    # Labels, units and decimals are the CLI's readable table's (KEYS).
    assert f"{s['mean_torque_nm']:,.2f}</td><td>N m</td>" in html
    assert f"{s['flywheel_inertia_kg_m2']:,.5f}</td><td>kg m²</td>" in html
    with pytest.raises(KeyError):
        ed._native.shown("models")
    b = session().batch(["data/single.csv", "no/such.csv"], jobs=1)
    bh = b._repr_html_()
    assert "<th>IMEP (bar)</th>" in bh and f"{s['imep_bar']:,.3f}" in bh and "error: " in bh


def test_a_result_saves_and_loads(tmp_path):
    r = session().analyse("data/single.csv")
    folder = r.to_folder(tmp_path / "run")
    assert sorted(os.listdir(folder)) == sorted(
        [n for n, _ in r.files()] + ["enginedyn-result.json", "enginedyn-summary.parquet", ".enginedyn-manifest"]
    )
    same_result(r, ed.Result.load(folder))
    with pytest.raises(FileNotFoundError):
        ed.Result.load(tmp_path)


# ---------------------------------------------------------------- item 18


def test_the_readme_says_the_install_compiles_how_long_and_how_to_reuse_it():
    text = open("README.md").read()
    at = text.index('pip install "./crates/python[pandas]"')
    section = text[at : at + 1200]
    assert "compiles" in section and "minutes" in section
    assert "pip wheel ./crates/python -w dist/" in section


# ------------------------------------------------ items 14-16, enginedyn.io


def four_cylinder_mdf(path, unit="V"):
    asammdf = pytest.importorskip("asammdf")
    t, v, tdc = record()
    mdf = asammdf.MDF(version="4.10")
    mdf.append(
        [asammdf.Signal(v, t, name=f"P_Cyl{k}", unit=unit) for k in range(1, 5)]
        + [asammdf.Signal(tdc, t, name="TDC", unit="V")]
    )
    mdf.save(str(path), overwrite=True)
    return t, v, tdc


def test_read_mdf_feeds_four_cylinders_to_analyse_time_record(tmp_path):
    path = tmp_path / "four.mf4"
    t, v, tdc = four_cylinder_mdf(path)
    a = ed.io.read_mdf(path, pressure=[f"P_Cyl{k}" for k in range(1, 5)], tdc="TDC")
    assert sorted(a) == ["pressure_v", "tdc", "time_s"] and a["pressure_v"].shape == (4, len(t))
    s = ed.Session(
        ed.Engine.from_toml("data/vaz2108.toml"),
        reader=ed.Reader(gain_bar_per_v=20.0, peg_bar=0.95, compression_check=False),
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        got = s.analyse_time_record(**a).summary
        want = s.analyse_time_record(t, pressure_v=np.vstack([v] * 4), tdc=tdc).summary
    got.pop("inputs"), want.pop("inputs")
    assert got == want


def test_a_four_cylinder_mdf4_time_record_reads_as_four_cylinders(cli, tmp_path):
    """Item 15's file route: `P_Cyl1..4` in one MDF4 time record are four
    cylinders on cylinder 1's crank angle (its TDC pulse), each moved onto
    its own firing TDC, and the file gives what its arrays give. Each
    cylinder here is cylinder 1's trace, late by its firing angle (vaz2108:
    0, 540, 180, 360°). Today's main refused the file as "one cycle per
    column is read against crank angle, not time"."""
    asammdf = pytest.importorskip("asammdf")
    t, v, tdc = record()
    up = np.flatnonzero((tdc[1:] > 2.5) & (tdc[:-1] <= 2.5))
    per_deg = np.mean(np.diff(up)) / 360.0
    p = np.vstack([np.roll(v, int(round(f * per_deg))) for f in (0, 540, 180, 360)])
    path = tmp_path / "four.mf4"
    mdf = asammdf.MDF(version="4.10")
    mdf.append(
        [asammdf.Signal(p[k], t, name=f"P_Cyl{k + 1}", unit="V") for k in range(4)]
        + [asammdf.Signal(tdc, t, name="TDC", unit="V")]
    )
    mdf.save(str(path), overwrite=True)
    flags = ["--gain", "20", "--peg-bar", "0.95", "--no-compression-check"]
    run = subprocess.run(
        [cli, "run", "--engine", "data/vaz2108.toml", "--diagram", str(path), *flags, "--json"],
        capture_output=True,
        text=True,
    )
    assert run.returncode == 0, run.stderr
    want = json.loads(run.stdout)
    assert any("4 pressure columns, one per cylinder" in n for n in want["notes"]), want["notes"]
    assert any("one shared crank angle" in n for n in want["notes"]), want["notes"]
    s = ed.Session(
        ed.Engine.from_toml("data/vaz2108.toml"),
        reader=ed.Reader(gain_bar_per_v=20.0, peg_bar=0.95, compression_check=False),
    )
    a = ed.io.read_mdf(path, pressure=[f"P_Cyl{k}" for k in range(1, 5)], tdc="TDC")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        from_file = s.analyse(path).summary
        from_arrays = s.analyse_time_record(**a).summary
    for got in (from_file, from_arrays):
        for k, x in want.items():
            if isinstance(x, float):
                assert got[k] == x, k
    # Each cylinder on its own TDC: a cycle of the same engine, so an IMEP
    # within the record's cycle-to-cycle spread (9.0 to 9.9 bar measured);
    # left on cylinder 1's angle, cylinders 2 and 3 would give their
    # gas-exchange loop (under 2 bar).
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        imep = s.analyse(path).cycles["imep_bar"]
    assert len(imep) == 4 and min(imep) > 0.85 * max(imep), imep


def test_read_mdf_lists_the_channels_and_refuses_a_unitless_pressure(tmp_path):
    path = tmp_path / "four.mf4"
    four_cylinder_mdf(path, unit="")
    with pytest.raises(KeyError) as e:
        ed.io.read_mdf(path, pressure="P_Cyl9", tdc="TDC")
    assert e.value.args[0] == "no channel 'P_Cyl9'; the channels are P_Cyl1, P_Cyl2, P_Cyl3, P_Cyl4, TDC, time"
    with pytest.raises(ValueError) as e:
        ed.io.read_mdf(path, pressure="P_Cyl1", tdc="TDC")
    assert str(e.value) == (
        "channel 'P_Cyl1' has no unit: give it with unit= (bar, kPa, MPa, psi or V), as a file's column names it"
    )
    a = ed.io.read_mdf(path, pressure="P_Cyl1", tdc="TDC", unit="V")
    assert "pressure_v" in a


def single_cycle():
    rows = [r for r in open("data/single.csv").read().splitlines() if r and not r.startswith("#")]
    data = np.array([r.split(",") for r in rows[1:]], dtype=float)
    return data[:, 0], data[:, 1]


def test_arrays_in_psi_or_mpa_are_named_as_files_are():
    s = session()
    a, p = single_cycle()
    with pytest.raises(ed.DiagramError) as e:
        s.analyse_arrays(a, p / 0.0689475729316836)
    assert "a pressure in psi read as bar" in str(e.value) and "`pressure [psi]`" in str(e.value)
    with pytest.raises(ed.DiagramError) as e:
        s.analyse_arrays(a, p / 10.0)
    assert "; or a pressure in MPa read as bar (0.095 MPa is 0.95 bar)" in str(e.value)


def test_a_time_in_ms_is_named_against_operating_rpm():
    s = session(gain_bar_per_v=20.0, peg_bar=0.95)
    t, v, tdc = record()
    with pytest.raises(ed.DiagramError) as e:
        s.analyse_time_record(t * 1e3, pressure_v=v, tdc=tdc)
    assert "a time in ms read as seconds?" in str(e.value) and "operating.rpm" in str(e.value)


# ------------------------------------------------------------- issue 37, A 6


def test_a_file_named_twice_is_one_row(tmp_path):
    """`Session.batch` lists files as a campaign does: `a.csv`, `./a.csv`
    and its absolute path are one file, analysed once, with a warning that
    names them (today's main gave three rows)."""
    import os

    names = ["data/single.csv", "./data/single.csv", os.path.abspath("data/single.csv"), "data/vaz2108.csv"]
    with pytest.warns(ed.EnginedynWarning, match="named more than once, analysed once by its canonical path") as w:
        b = session().batch(names, jobs=1)
    assert b.files == ["data/single.csv", "data/vaz2108.csv"]
    said = [str(x.message) for x in w if "named more than once" in str(x.message)]
    assert len(said) == 1 and "./data/single.csv" in said[0], said
