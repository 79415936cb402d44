"""A test campaign from a notebook: every bench file of a folder through a
Dask LocalCluster into Parquet parts, then a polars group-by and a chart.

    python examples/campaign.py [FOLDER] [ENGINE] [OUT]

Defaults: the measured fixtures of this repository and its one-cylinder
engine (several files of which fail on purpose: they show as error rows).
Needs `pip install ./crates/python[polars,dask]` (matplotlib for the chart).
"""

import pathlib
import sys

import polars as pl
from dask.distributed import Client, LocalCluster

import enginedyn as ed
from enginedyn.dask import map_campaign

root = pathlib.Path(__file__).resolve().parents[1]
folder = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else root / "tests/fixtures/measured"
engine = pathlib.Path(sys.argv[2]) if len(sys.argv) > 2 else root / "data/single.toml"
out = pathlib.Path(sys.argv[3]) if len(sys.argv) > 3 else pathlib.Path("campaign_out")

kinds = {".csv", ".txt", ".dat", ".tsv", ".xlsx", ".xls", ".ods", ".mf4"}
paths = sorted(str(p) for p in folder.iterdir() if p.suffix.lower() in kinds)
session = ed.Session(ed.Engine.from_toml(engine))

if __name__ == "__main__":
    with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as cluster, Client(cluster) as client:
        manifest = map_campaign(client, session, paths, out, files_per_task=10)
    print(f"{manifest['files']} files in {manifest['parts']} parts, {manifest['failed']} failed, {manifest['cycles']} cycles")

    summary = pl.read_parquet(str(out / "summary" / "*.parquet"))
    cycles = pl.read_parquet(str(out / "cycles" / "*.parquet"))
    per_file = (
        cycles.filter(pl.col("used"))
        .group_by("file")
        .agg(
            pl.len().alias("cycles"),
            pl.col("imep_bar").mean().alias("imep_bar"),
            (pl.col("imep_bar").std() / pl.col("imep_bar").mean() * 100).alias("imep_cov_percent"),
            pl.col("p_max_bar").max().alias("p_max_bar"),
        )
        .sort("imep_bar")
    )
    print(per_file)
    print(summary.filter(pl.col("error").is_not_null()).select("file", "error"))

    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("(matplotlib not installed: no chart)")
    else:
        fig, ax = plt.subplots(figsize=(8, 4))
        names = [pathlib.Path(f).name for f in per_file["file"]]
        ax.barh(names, per_file["imep_bar"])
        ax.set_xlabel("mean IMEP of the cycles used (bar)")
        fig.tight_layout()
        fig.savefig(out / "imep_by_file.png", dpi=100)
        print(f"chart: {out / 'imep_by_file.png'}")
