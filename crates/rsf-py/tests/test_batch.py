"""fit_many / diagnose_many: the same table as `rsf batch`, on a Dask LocalCluster of two
worker processes and without a cluster; a failing record is a row, not an exception."""

import os
import shutil
import subprocess
import types

import pandas as pd
import pytest

import rsf

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))
CLI = os.path.join(ROOT, "target", "release", "rsf")
BASALT = os.path.join(ROOT, "examples", "data", "giacomel-basalt", "velstep4_BRAVA_expb819_basalt.txt")
NS = ["ns_small_a0_s+30.csv", "ns_small_a0.3_s-20.csv"]


@pytest.fixture(scope="module")
def lab(tmp_path_factory):
    d = tmp_path_factory.mktemp("lab")
    shutil.copy(BASALT, d / "basalt.txt")
    (d / "ns").mkdir()
    for f in NS:
        shutil.copy(os.path.join(ROOT, "tests", "data", "normal_stress", f), d / "ns" / f)
    (d / "bad.csv").write_text("time_s,load_point_um,mu\n0,0,0.6\n1,1,0.6\n2,2,0.6x\n")
    (d / "manifest.csv").write_text(
        "file,stiffness,time_col,lp_col,mu_col,normal_col,loading,meta_sample\n"
        "basalt.txt,0.0151,Time(s),Displ(microns),Friction,,protocol,BRAVA b819\n"
        f"ns/{NS[0]},0.01,,lp_um,,normal_stress_mpa,,S2\n"
        f"ns/{NS[1]},0.01,,lp_um,,normal_stress_mpa,,S3\n"
        "bad.csv,0.01,,,,,,S4\n")
    return d


def batch_summary(lab, *flags):
    if not os.path.exists(CLI):
        pytest.skip("target/release/rsf not built (cargo build --release -p rsf-cli)")
    out = lab / ("out" + "".join(flags))
    r = subprocess.run([CLI, "batch", str(lab / "manifest.csv"), "--out", str(out), *flags],
                       capture_output=True, text=True)
    assert r.returncode == 1, r.stderr          # one record fails: reported, exit status 1
    assert "bad.csv: read_failed" in r.stdout
    return typed_csv(out / "summary.csv")


TEXT = {"file", "status", "error", "laws", "cause", "effect", "runner_up", "partial", "adequacy"}
COUNTS = {"samples", "events_tested", "events"}


def typed_csv(path):
    """summary.csv read without pandas' type guessing, each column typed as rsf batch types it:
    text as written, ``samples`` and the events tested counts, every other column a number."""
    raw = pd.read_csv(path, dtype=str, keep_default_na=False)
    out = {}
    for c in raw.columns:
        if c in TEXT or c.startswith("meta_"):
            out[c] = raw[c].astype(object)
        elif c in COUNTS:
            out[c] = pd.to_numeric(raw[c].replace("", None)).astype("Int64")
        else:
            out[c] = pd.to_numeric(raw[c].replace("", None)).astype("float64")
    return pd.DataFrame(out)


@pytest.fixture(scope="module")
def client():
    distributed = pytest.importorskip("distributed")
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       dashboard_address=None)
    c = distributed.Client(cluster)
    yield c
    c.close()
    cluster.close()


def test_diagnose_many_on_dask_equals_rsf_batch(lab, client):
    want = batch_summary(lab, "--diagnose")
    got = rsf.diagnose_many(lab / "manifest.csv", client=client)
    pd.testing.assert_frame_equal(got, want)
    assert list(got["status"]) == ["ok", "ok", "ok", "read_failed"]
    assert got.loc[3, "error"].endswith("column `mu`: `0.6x` is not a number")
    assert got["cause"].iloc[:3].notna().all() and (got["a_se"].iloc[:3] > 0).all()
    # the adequacy test's coverage: of the record's events, those it could judge
    assert (got["events"].iloc[:3] >= 1).all() and (got["events_tested"].iloc[:3] <= got["events"].iloc[:3]).all()
    # the quiet test's ratio: a number where the named model's quiet stretches could be measured
    assert "quiet_wander" in got.columns and (got["quiet_wander"].dropna() > 0).all()
    assert "form_delta_bic" in got.columns and "lead_z" in got.columns
    assert list(got["meta_sample"]) == ["BRAVA b819", "S2", "S3", "S4"]


def test_fit_many_with_and_without_a_cluster_equals_rsf_batch(lab, client):
    want = batch_summary(lab, "--fit")
    pd.testing.assert_frame_equal(rsf.fit_many(lab / "manifest.csv", client=client), want)
    pd.testing.assert_frame_equal(rsf.fit_many(str(lab / "manifest.csv")), want)


def test_paths_with_options_given_once(lab):
    paths = [lab / "ns" / f for f in NS]
    df = rsf.fit_many(paths, stiffness=0.01, lp_col="lp_um", normal_col="normal_stress_mpa")
    assert list(df["status"]) == ["ok", "ok"]
    assert (df["normal_stress_mpa"] == 10).all()
    with pytest.raises(TypeError, match="unknown option"):
        rsf.fit_many(paths, stiffness=0.01, lp_column="lp_um")
    with pytest.raises(ValueError, match="loading"):
        rsf.fit_many(paths, stiffness=0.01, loading="recrd")
    df = rsf.fit_many(paths, lp_col="lp_um")         # no stiffness anywhere: each record says so
    assert list(df["status"]) == ["options_invalid"] * 2


def test_a_law_file_in_the_manifest_reaches_dask_workers(tmp_path, client):
    # issue 39: a manifest's `law_file` column registers its law in this process and, again,
    # in each worker process, which knows only the built-in laws otherwise
    shutil.copy(os.path.join(ROOT, "tests", "data", "outside", "power_aging.csv"), tmp_path / "pa.csv")
    shutil.copy(os.path.join(ROOT, "examples", "laws", "power_aging.toml"), tmp_path / "power.toml")
    (tmp_path / "manifest.csv").write_text("file,stiffness,law_file,law\npa.csv,0.02,power.toml,power-aging\n")
    df = rsf.fit_many(tmp_path / "manifest.csv", client=client)
    assert list(df["status"]) == ["ok"], df.get("error")
    assert df.loc[0, "laws"] == "power-aging"
    n = [c for c in df.columns if c.startswith("n1")]
    assert n and abs(df.loc[0, "n1"] - 1.5) < 0.01, list(df.columns)


def test_a_record_outside_the_manifests_folder_is_refused(tmp_path):
    # issue 40: on the main before it, `../x.csv` was read (and its first line could reach the
    # summary's error cell)
    (tmp_path / "lab").mkdir()
    shutil.copy(BASALT, tmp_path / "x.txt")
    (tmp_path / "lab" / "manifest.csv").write_text("file,stiffness\n../x.txt,0.0151\n")
    with pytest.raises(ValueError, match="outside the manifest's folder"):
        rsf.fit_many(tmp_path / "lab" / "manifest.csv")
    df = rsf.fit_many(tmp_path / "lab" / "manifest.csv", allow_outside=True, time_col="Time(s)",
                      lp_col="Displ(microns)", mu_col="Friction", loading="protocol")
    assert list(df["status"]) == ["ok"], df.get("error")


def test_a_non_finite_option_is_said_in_the_users_terms(tmp_path):
    # issue 40 (defect 12): on the main, "expected value at line 1 column 34"
    with pytest.raises(ValueError, match=r"stiffness = nan must be a finite number"):
        rsf.fit_many([tmp_path / "x.csv"], stiffness=float("nan"))


def test_meta_cells_stay_text_and_formulas_stay_raw(tmp_path):
    """Issue 40: the table is built from the typed rows, not by pandas guessing types from
    CSV text: a meta `NA` stays "NA" (read_csv made it NaN), `007` stays "007" (it made it 7),
    and `=1+1` is the manifest's text (summary.csv quotes it as `'=1+1` for spreadsheets)."""
    shutil.copy(BASALT, tmp_path / "basalt.txt")
    (tmp_path / "manifest.csv").write_text(
        "file,stiffness,time_col,lp_col,mu_col,meta_a,meta_id,meta_f\n"
        "basalt.txt,0.0151,Time(s),Displ(microns),Friction,NA,007,=1+1\n")
    got = rsf.fit_many(tmp_path / "manifest.csv")
    assert got.loc[0, "meta_a"] == "NA" and got.loc[0, "meta_id"] == "007" and got.loc[0, "meta_f"] == "=1+1"
    assert got["samples"].dtype == "Int64" and got["a"].dtype == "float64"


def test_a_task_that_fails_is_a_crashed_row_and_the_others_are_kept(lab, monkeypatch):
    """Issue 40: on Dask, a record whose task fails (a worker it keeps killing ends in
    KilledWorker) was an exception that lost every finished row; it is now a `crashed` row."""
    distributed = pytest.importorskip("distributed")
    import rsf.batch as b
    real = b._row

    def dies_on_ns(entry_json, *a, **k):
        if NS[0] in entry_json:
            worker = types.SimpleNamespace(address="tcp://127.0.0.1:1")  # what KilledWorker names
            raise distributed.KilledWorker("rsf-test", worker, 3)
        return real(entry_json, *a, **k)

    monkeypatch.setattr(b, "_row", dies_on_ns)
    cluster = distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None)
    c = distributed.Client(cluster)
    try:
        got = rsf.fit_many(lab / "manifest.csv", client=c)
    finally:
        c.close()
        cluster.close()
    assert list(got["status"]) == ["ok", "crashed", "ok", "read_failed"]
    assert "KilledWorker" in got.loc[1, "error"] and got.loc[1, "meta_sample"] == "S2"
