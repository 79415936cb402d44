"""The combustion analysis from Python: the same keywords as the CLI's
flags (checked by the library), the same figures, and the cycles table's
combustion columns."""

import json
import subprocess

import pytest

import enginedyn as ed


def test_burn_keywords_are_checked_by_the_library():
    with pytest.raises(ed.UsageError, match="gamma"):
        ed.Method(gamma=2.5)
    with pytest.raises(ed.UsageError, match="burn_points"):
        ed.Method(burn_points=[0, 50])
    with pytest.raises(ed.UsageError, match="smooth"):
        ed.Method(smooth="box:3")
    with pytest.raises(ed.UsageError, match="brunt"):
        ed.Method(ivc_deg=-150)
    m = ed.Method(burn_points=[90, 50, 25], burn_window=(-60, 100), gamma="brunt", smooth="SG:3")
    assert m.gamma == "brunt"


def test_python_and_the_cli_give_one_burn(cli):
    flags = ["--burn-points", "10,25,50,90", "--gamma", "brunt", "--smooth", "SG:3"]
    r = subprocess.run([cli, "run", "--engine", "data/single.toml", "--json", *flags], capture_output=True, text=True, check=True)
    want = json.loads(r.stdout)
    s = ed.Session(
        ed.Engine.from_toml("data/single.toml"),
        method=ed.Method(burn_points=[10, 25, 50, 90], gamma="brunt", smooth="SG:3"),
    )
    got = s.analyse("data/single.csv").summary
    for k in ["ca10_deg", "ca25_deg", "ca50_deg", "ca90_deg", "heat_released_j", "dp_dphi_max_bar_deg", "imep_gross_bar", "pmep_bar"]:
        assert got[k] == want[k], k
    assert got["models"]["gamma"].startswith("brunt")
    assert -30 < got["ca50_deg"] < 40


def test_cycles_carry_the_combustion_columns():
    s = ed.Session(ed.Engine.from_toml("data/single.toml"))
    b = s.batch(["data/single.csv"], jobs=1)
    t = b.cycles_arrow()
    for c in ["imep_gross_bar", "pmep_bar", "ca50_deg", "burn_10_90_deg", "dp_dphi_max_bar_deg", "combustion"]:
        assert c in t.column_names, c
    summary = b.to_arrow()
    assert "ca50_deg" in summary.column_names and "dp_dphi_max_bar_deg" in summary.column_names
