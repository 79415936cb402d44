"""enginedyn.io: a DAQ record written as MDF4 (asammdf), TDMS (npTDMS) and
HDF5 (h5py), units as each tool stores them, reads to the CLI's summary
of the same record as CSV."""

import csv
import json
import subprocess

import numpy as np
import pytest

import enginedyn as ed
from enginedyn import io

RECORD = "tests/fixtures/measured/daq_72khz_tdc.csv"
FLAGS = ["--gain", "20", "--peg-bar", "0.95"]


def record():
    rows = list(csv.reader(open(RECORD)))
    data = np.array(rows[1:], dtype=float)
    return data[:, 0], data[:, 1], data[:, 2]


@pytest.fixture(scope="module")
def want(cli):
    p = subprocess.run(
        [cli, "run", "--engine", "data/single.toml", "--diagram", RECORD, *FLAGS, "--json"],
        capture_output=True,
        text=True,
        check=True,
    )
    s = json.loads(p.stdout)
    s.pop("inputs")
    return s


def session():
    return ed.Session(
        ed.Engine.from_toml("data/single.toml"),
        reader=ed.Reader(gain_bar_per_v=20.0, peg_bar=0.95),
    )


def check(arrays, want, time_scale_exact=True):
    r = session().analyse_time_record(**arrays)
    got = r.summary
    got.pop("inputs")
    if time_scale_exact:
        assert got == want
    else:
        assert abs(got["imep_bar"] - want["imep_bar"]) <= 1e-12 * abs(want["imep_bar"])


def test_mdf4_time_master_compressed(tmp_path, want):
    asammdf = pytest.importorskip("asammdf")
    t, v, tdc = record()
    mdf = asammdf.MDF(version="4.10")
    mdf.append(
        [
            asammdf.Signal(v, t, name="P_cyl1", unit="V"),
            asammdf.Signal(tdc, t, name="TDC", unit="V"),
        ]
    )
    path = tmp_path / "record.mf4"
    mdf.save(path, compression=2)
    arrays = io.read_mdf(path, pressure="P_cyl1", tdc="TDC")
    assert set(arrays) == {"time_s", "pressure_v", "tdc"}
    check(arrays, want)


def test_tdms_waveform_in_ms(tmp_path, want):
    nptdms = pytest.importorskip("nptdms")
    t, v, tdc = record()
    path = tmp_path / "record.tdms"
    with nptdms.TdmsWriter(path) as w:
        w.write_segment(
            [
                nptdms.ChannelObject("bench", "time", t * 1e3, properties={"unit_string": "ms"}),
                nptdms.ChannelObject("bench", "Pcyl", v, properties={"unit_string": "V"}),
                nptdms.ChannelObject("bench", "tdc", tdc, properties={"unit_string": "V"}),
            ]
        )
    arrays = io.read_tdms(path, "bench", pressure="Pcyl", time="time", tdc="tdc")
    np.testing.assert_allclose(arrays["time_s"], t, rtol=1e-15, atol=0)
    check(arrays, want, time_scale_exact=False)


def test_hdf5_with_unit_attributes(tmp_path, want):
    h5py = pytest.importorskip("h5py")
    t, v, tdc = record()
    path = tmp_path / "record.h5"
    with h5py.File(path, "w") as f:
        f["bench/time"] = t
        f["bench/time"].attrs["unit"] = "s"
        f["bench/p_cyl1"] = v
        f["bench/p_cyl1"].attrs["units"] = "V"
        f["bench/tdc"] = tdc
    arrays = io.read_hdf5(path, pressure="bench/p_cyl1", time="bench/time", tdc="bench/tdc")
    check(arrays, want)


def test_units_convert_by_the_readers_tables():
    assert io.convert("P_cyl1", "MPa", [1.0])[0] == "pressure_bar"
    assert io.convert("P_cyl1", "MPa", [1.0])[1][0] == 10.0
    key, v = io.convert("Crank angle", "rad", [np.pi])
    assert key == "angle_deg" and abs(v[0] - 180.0) < 1e-12
    with pytest.raises(ValueError, match="not a crank angle"):
        io.convert("Lambda", "-", [1.0])
