"""Campaigns: shards add up to one batch, parts read back in pyarrow,
polars and pandas with the schema, nulls and metadata INTERFACE.md gives,
parts of a 4- and a 12-cylinder campaign concatenate, merge names a
missing part, and Dask's map_campaign gives batch's rows."""

import glob
import json
import os
import subprocess

import pytest

import enginedyn as ed

pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")

FILES = sorted(glob.glob("data/*.csv")) + ["tests/fixtures/measured/dropout_20cycles.csv", "no/such.csv"]


def batch(cli, out, *flags):
    return subprocess.run(
        [cli, "batch", "--engine", "data/single.toml", *FILES, "--parquet", str(out), *flags],
        capture_output=True,
        text=True,
    )


def read(dir, table):
    return pq.read_table(os.path.join(dir, table))


def test_shards_add_up_to_one_batch(cli, tmp_path):
    whole = batch(cli, tmp_path / "whole")
    assert whole.returncode == 0, whole.stderr
    for i in range(3):
        p = batch(cli, tmp_path / "sharded", "--shard", f"{i}/3")
        assert p.returncode == 0, p.stderr
    for table in ("summary", "cycles"):
        one = read(tmp_path / "whole", table).sort_by([("file", "ascending")] + ([("cylinder", "ascending"), ("cycle", "ascending")] if table == "cycles" else []))
        parts = read(tmp_path / "sharded", table).sort_by([("file", "ascending")] + ([("cylinder", "ascending"), ("cycle", "ascending")] if table == "cycles" else []))
        assert one.num_rows == parts.num_rows > 0
        assert one.to_pylist() == parts.to_pylist()
    m = subprocess.run([cli, "merge", str(tmp_path / "sharded")], capture_output=True, text=True)
    assert m.returncode == 0, m.stderr
    manifest = json.loads((tmp_path / "sharded" / "_manifest.json").read_text())
    failed = sum(e is not None for e in read(tmp_path / "whole", "summary").column("error").to_pylist())
    assert failed >= 1
    assert (manifest["parts"], manifest["files"], manifest["failed"]) == (3, len(FILES), failed)
    os.remove(tmp_path / "sharded" / "summary" / "part-00001-of-00003.parquet")
    os.remove(tmp_path / "sharded" / "_manifest.json")
    m = subprocess.run([cli, "merge", str(tmp_path / "sharded")], capture_output=True, text=True)
    assert m.returncode == 1 and "part-00001-of-00003" in m.stderr and "missing" in m.stderr
    assert not (tmp_path / "sharded" / "_manifest.json").exists()


def test_parts_read_back_with_schema_nulls_and_metadata(cli, tmp_path):
    assert batch(cli, tmp_path / "c", "--traces").returncode == 0
    path = tmp_path / "c" / "summary" / "part-00000-of-00001.parquet"
    t = pq.read_table(path)
    meta = {k.decode(): v.decode() for k, v in t.schema.metadata.items() if not k.startswith(b"ARROW")}
    assert meta["enginedyn.schema"] == "summary/4"
    assert meta["enginedyn.version"] == ed.__version__
    options = json.loads(meta["options"])
    assert len(meta["engine.blake3"]) == 64 and len(meta["engine.parsed_blake3"]) == 64
    # The options as used, defaults filled in (merge compares by meaning).
    assert options["reader"] == {} and options["method"]["step_deg"] == 0.1 and options["method"]["interp"] == "auto"
    campaign = json.loads(meta["enginedyn.campaign"])
    assert (campaign["parts"], campaign["part"], campaign["tables"]) == (1, 0, ["summary", "cycles", "traces"])
    assert len(campaign["list_blake3"]) == 64
    names = t.schema.names
    assert names[:4] == ["file", "error", "engine", "diagram_blake3"]
    assert t.schema.field("journal_most_loaded").type == pa.int32()
    assert t.schema.field("cycles").type == pa.int64()
    # summary/3 appends the peak pressure, wall heat, knock and the level
    # lists; summary/4 the brake figures and design.*.
    assert names[-10:-8] == ["burn_levels_pct", "burn_levels_deg"] and "imep_lnv" in names and "p_max_bar" in names
    assert names[-8:] == ["fmep_bar", "bmep_bar", "brake_torque_nm", "brake_power_kw", "mechanical_efficiency", "design.charge", "design.intake_pressure_bar", "design.lambda"]
    assert t.schema.field("burn_levels_deg").type == pa.list_(pa.float64())
    assert "ca50_deg" in names and "models.grid_step_deg" in names and "pegging.method" in names
    rows = {r["file"]: r for r in t.to_pylist()}
    failed = rows["no/such.csv"]
    assert failed["error"].startswith("cannot open") and failed["imep_bar"] is None
    single = rows["data/single.csv"]
    cli_json = json.loads(
        subprocess.run([cli, "run", "--engine", "data/single.toml", "--diagram", "data/single.csv", "--json"], capture_output=True, text=True).stdout
    )
    assert single["imep_bar"] == cli_json["imep_bar"] and single["error"] is None
    assert single["pegging.offset_bar"] is None  # absent key: null
    cycles = read(tmp_path / "c", "cycles").to_pylist()
    dropout = [c for c in cycles if c["file"].endswith("dropout_20cycles.csv")]
    assert len(dropout) == 20 and sum(not c["used"] for c in dropout) == 2
    assert all(c["skip_reason"] is None for c in dropout if c["used"])
    traces = read(tmp_path / "c", "traces")
    assert pq.read_schema(tmp_path / "c" / "traces" / "part-00000-of-00001.parquet").metadata[b"enginedyn.schema"] == b"traces/1"
    ran = sum(r["error"] is None for r in rows.values())
    # One trace (cylinder 0) of 7200 points (0.1° over 720°) per file that ran.
    assert traces.num_rows == 7200 * ran
    assert set(traces.column("cylinder").to_pylist()) == {0}


def test_polars_and_pandas_read_the_parts(cli, tmp_path):
    pl = pytest.importorskip("polars")
    pd = pytest.importorskip("pandas")
    assert batch(cli, tmp_path / "p").returncode == 0
    df = pl.read_parquet(str(tmp_path / "p" / "summary" / "*.parquet"))
    assert df.height == len(FILES) and df["imep_bar"].null_count() >= 1
    pdf = pd.read_parquet(tmp_path / "p" / "summary")
    assert len(pdf) == len(FILES)


def test_four_and_twelve_cylinder_parts_concatenate(cli, tmp_path):
    for name in ("vaz2108", "v12_60"):
        p = subprocess.run(
            [cli, "batch", "--engine", f"data/{name}.toml", f"data/{name}.csv", "--parquet", str(tmp_path / name)],
            capture_output=True,
            text=True,
        )
        assert p.returncode == 0, p.stderr
    for table in ("summary", "cycles"):
        a = read(tmp_path / "vaz2108", table)
        b = read(tmp_path / "v12_60", table)
        assert a.schema.remove_metadata() == b.schema.remove_metadata()
        both = pa.concat_tables([a.replace_schema_metadata(None), b.replace_schema_metadata(None)])
        assert both.num_rows == a.num_rows + b.num_rows


def test_python_writes_the_clis_parts(cli, tmp_path):
    assert batch(cli, tmp_path / "cli").returncode == 0
    s = ed.Session(ed.Engine.from_toml("data/single.toml"))
    b = s.batch(FILES, jobs=2)
    b.write_parquet(tmp_path / "py")
    for table in ("summary", "cycles"):
        name = f"{table}/part-00000-of-00001.parquet"
        assert (tmp_path / "py" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()
    assert b.to_arrow().equals(read(tmp_path / "cli", "summary"))
    pl = pytest.importorskip("polars")
    assert b.to_polars().height == len(FILES)


def test_dask_map_campaign_gives_the_batchs_rows(tmp_path):
    distributed = pytest.importorskip("distributed")
    from enginedyn import dask as ed_dask

    s = ed.Session(ed.Engine.from_toml("data/single.toml"))
    files = FILES * 3
    # A file named three times is one file of the campaign, analysed once.
    assert sum(len(x) for x in ed_dask.shards(files, 4)) == len(FILES)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            manifest = ed_dask.map_campaign(client, s, files, tmp_path / "dask", files_per_task=10)
    assert manifest["files"] == len(FILES) and manifest["parts"] == 3
    got = read(tmp_path / "dask", "summary").sort_by("file")
    want = s.batch(FILES, jobs=1).to_arrow().sort_by("file")
    assert got.replace_schema_metadata(None).to_pylist() == want.replace_schema_metadata(None).to_pylist()


def test_a_campaign_run_again_into_its_folder(tmp_path):
    """The same campaign mapped twice into one folder, its parts running at
    once: a task's check of the folder may list a part that its own task is
    replacing (removed, then moved in). That part is the same campaign's,
    not "a file without enginedyn's metadata in the way" (the second run
    failed so, 1 time in 1, before the check let it pass; 8 parts on 2
    workers)."""
    distributed = pytest.importorskip("distributed")
    from enginedyn import dask as ed_dask

    s = ed.Session(ed.Engine.from_toml("data/single.toml"))
    text = open("data/single.csv").read()
    files = []
    for k in range(16):
        files.append(str(tmp_path / f"c{k:02}.csv"))
        with open(files[-1], "w") as f:
            f.write(text)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            for _ in range(3):
                manifest = ed_dask.map_campaign(client, s, files, tmp_path / "out", files_per_task=2)
                assert manifest["files"] == 16 and manifest["parts"] == 8


def test_map_campaign_refuses_another_campaigns_folder_before_any_work(cli, tmp_path):
    """Issue 37, item 4: no client is needed to be refused (nothing runs)."""
    from enginedyn import dask as ed_dask

    out = tmp_path / "c"
    assert batch(cli, out).returncode == 0
    s = ed.Session(ed.Engine.from_toml("data/single.toml"))
    with pytest.raises(OSError) as e:
        ed_dask.map_campaign(None, s, FILES[:2], out, files_per_task=1)
    msg = str(e.value)
    assert "summary/part-00000-of-00001.parquet: holds a campaign of 1 part over the file list " in msg
    assert ", not this one (a campaign of 2 parts over the file list " in msg and "overwrite=True" in msg
    # overwrite=True removes enginedyn's parts (a client is needed from there on).
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            manifest = ed_dask.map_campaign(client, s, FILES[:2], out, files_per_task=1, overwrite=True)
    assert (manifest["files"], manifest["parts"]) == (2, 2)


def test_run_shard_parts_are_map_campaigns(tmp_path):
    """`run_shard` over every part (what each Slurm task or worker runs),
    then `check_campaign`, gives the campaign `map_campaign` gives: the
    same manifest and the same rows; a part outside 0..N-1 is the
    library's UsageError."""
    from enginedyn import dask as ed_dask

    s = ed.Session(ed.Engine.from_toml("data/single.toml"))
    got = [ed_dask.run_shard(s, FILES, tmp_path / "shards", i, 3) for i in range(3)]
    assert sum(g["files"] for g in got) == len(FILES)
    manifest = ed_dask.check_campaign(tmp_path / "shards", 3)
    assert manifest["files"] == len(FILES) and manifest["parts"] == 3
    rows = read(tmp_path / "shards", "summary").sort_by("file")
    want = s.batch(FILES, jobs=1).to_arrow().sort_by("file")
    assert rows.replace_schema_metadata(None).to_pylist() == want.replace_schema_metadata(None).to_pylist()
    with pytest.raises(ed.UsageError, match="part/parts"):
        ed_dask.run_shard(s, FILES, tmp_path / "shards", 3, 3)
