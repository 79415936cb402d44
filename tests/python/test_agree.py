"""One library, two front ends: the Python package gives the CLI's
summary.json, bit for bit, and its errors, on every measured fixture and
every bundled engine; a file and the same data as arrays give one summary."""

import csv
import json
import subprocess

import numpy as np
import pytest

import enginedyn as ed

# CLI flags whose Python names are not the flag's own with `_` for `-`.
RENAMED = {"--max-gap": "max_gap_deg", "--gain": "gain_bar_per_v", "--no-compression-check": "compression_check"}
NUMERIC = {"tdc_deg", "peg_bar", "max_gap_deg", "tdc_time", "gain_bar_per_v", "rpm", "wheel_tdc_deg", "angle_step"}
INTEGER = {"encoder_ppr", "skip_lines", "group"}
SWITCHES = {"--gauge": True, "--no-compression-check": False, "--despike": True}


def reader_kwargs(flags):
    kw, i = {}, 0
    while i < len(flags):
        flag = flags[i]
        name = RENAMED.get(flag, flag[2:].replace("-", "_"))
        if flag in SWITCHES:
            kw[name] = SWITCHES[flag]
            i += 1
            continue
        value = flags[i + 1]
        if name == "columns":
            value = value.split(",")
        elif name in NUMERIC:
            value = float(value)
        elif name in INTEGER:
            value = int(value)
        kw[name] = value
        i += 2
    return kw


def cli_json(cli, root, args):
    p = subprocess.run([cli, *args, "--json"], cwd=root, capture_output=True, text=True)
    return p.returncode, (json.loads(p.stdout) if p.returncode == 0 else None), p.stderr


def fixtures(root):
    doc = json.loads((root / "tests/fixtures/measured/expected.json").read_text())
    return doc["engine"], doc["fixtures"]


def test_every_measured_fixture_agrees_with_the_cli(cli, root):
    engine_file, entries = fixtures(root)
    engine = ed.Engine.from_toml(str(root / engine_file))
    assert len(entries) >= 30
    checked = 0
    for e in entries:
        flags = e["flags"]
        code, want, err = cli_json(cli, root, ["run", "--engine", engine_file, "--diagram", e["file"], *flags])
        assert code == e["exit"], (e["id"], err)
        session = ed.Session(engine, reader=ed.Reader(**reader_kwargs(flags)))
        if code == 0:
            got = session.analyse(str(root / e["file"])).summary
            # `inputs` names the paths as given: the CLI's are relative.
            assert got["inputs"]["diagram_blake3"] == want["inputs"]["diagram_blake3"]
            got.pop("inputs"), want.pop("inputs")
            assert got == want, e["id"]
        else:
            with pytest.raises((ed.DiagramError, OSError)) as raised:
                session.analyse(str(root / e["file"]))
            # The same message (the path aside) as the CLI's error line,
            # its flags named as keywords by the one mapping.
            message = str(raised.value).split(": ", 1)[1]
            assert message in ed._native.in_keywords(err), (e["id"], message, err)
            if isinstance(raised.value, ed.DiagramError):
                assert raised.value.path == str(root / e["file"])
        checked += 1
    assert checked == len(entries)


@pytest.mark.parametrize("name", ed.Engine.bundled_names())
def test_every_bundled_engine_agrees_with_the_cli(cli, root, name):
    code, want, err = cli_json(cli, root, ["run", "--engine", f"data/{name}.toml"])
    assert code == 0, err
    got = ed.Session(ed.Engine.from_toml(f"data/{name}.toml")).analyse(f"data/{name}.csv").summary
    got.pop("inputs"), want.pop("inputs")
    assert got == want
    # The bundled copy is the same engine and diagram.
    bundled = ed.Session(ed.Engine.bundled(name)).analyse().summary
    bundled.pop("inputs")
    assert bundled == want


def read_long(path):
    rows = [r for r in csv.reader(open(path)) if r and not r[0].startswith("#")]
    return rows[0], np.array(rows[1:], dtype=float)


def test_a_file_and_its_arrays_give_one_summary(root):
    engine = ed.Engine.from_toml(str(root / "data/single.toml"))
    s = ed.Session(engine)
    from_file = s.analyse(str(root / "data/single.csv")).summary
    header, data = read_long(root / "data/single.csv")
    assert header[:2] == ["crank_deg", "pressure_bar"]
    from_arrays = s.analyse_arrays(data[:, 0], data[:, 1]).summary
    assert from_arrays["inputs"]["diagram_files"] == ["arrays"]
    from_file.pop("inputs"), from_arrays.pop("inputs")
    assert from_file == from_arrays
    # Other dtypes and strided views are converted, never refused.
    strided = s.analyse_arrays(list(data[:, 0]), np.asfortranarray(data)[:, 1].astype(np.float32)).summary
    assert abs(strided["imep_bar"] - from_file["imep_bar"]) < 1e-6 * from_file["imep_bar"]


def test_cycles_in_arrays_are_cycles(root):
    """A long layout (cycle column) from arrays gives the file's summary."""
    engine = ed.Engine.from_toml(str(root / "data/single.toml"))
    s = ed.Session(engine)
    path = root / "tests/fixtures/measured/dropout_20cycles.csv"
    rows = [r for r in csv.reader(open(path)) if r and not r[0].startswith("#")]
    names = [c.strip() for c in rows[0]]
    data = np.array(rows[1:], dtype=float)
    cols = {n: data[:, k] for k, n in enumerate(names)}
    from_file = s.analyse(str(path)).summary
    from_arrays = s.analyse_arrays(cols["crank_deg"], cols["pressure_bar"], cycle=cols["cycle"]).summary
    from_file.pop("inputs"), from_arrays.pop("inputs")
    assert from_file == from_arrays
    assert from_file["cycles_skipped"] == 2


def test_wrong_arrays_are_clear_errors(root):
    s = ed.Session(ed.Engine.from_toml(str(root / "data/single.toml")))
    with pytest.raises(ValueError, match="different lengths"):
        s.analyse_arrays(np.arange(10.0), np.arange(11.0))
    with pytest.raises(TypeError, match="angle_deg|crank_deg"):
        s.analyse_arrays(np.zeros((3, 3)), np.zeros(3))
    with pytest.raises(TypeError):
        s.analyse_arrays(["a", "b"], [1.0, 2.0])
    angle = np.arange(0.0, 720.0, 0.5)
    p = np.full_like(angle, 1.0)
    p[7] = np.nan
    with pytest.raises(ed.DiagramError) as e:
        s.analyse_arrays(angle, p)
    assert e.value.line == 8 and e.value.column == 2
