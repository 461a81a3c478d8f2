"""The SQLite result store: rows, replace-on-rerun, bad files, exports."""

import csv
import sqlite3

import pyarrow.parquet as pq
import pytest

from neurowalk.runners.specs import FIELDS, spec_key
from neurowalk.runners.store import EXPORT_META, ResultStore, StoreError
from neurowalk.sim.config import EpisodeConfig


def _spec(seed):
    return EpisodeConfig.from_spec({"arena": "box", "seed": seed, "steps": 30}).spec()


def test_put_rows_and_replace_error_by_ok(tmp_path):
    with ResultStore(tmp_path / "r.sqlite") as st:
        a, b = _spec(0), _spec(1)
        st.put(spec_key(a), a, result={"x": 1.5, "pose": [1, 2, 3]}, wall_time_s=0.1)
        st.put(spec_key(b), b, error="ValueError: nope")
        assert st.done_keys() == {spec_key(a)} and st.counts() == {"ok": 1, "error": 1} and len(st) == 2
        st.put(spec_key(b), b, result={"x": 2.0}, wall_time_s=0.2)  # a rerun replaces the error row
        assert len(st) == 2 and st.counts() == {"ok": 2, "error": 0}
        assert st.results() == {spec_key(a): {"x": 1.5, "pose": [1, 2, 3]}, spec_key(b): {"x": 2.0}}
        row = st.rows()[0]
        assert set(row) == {"key", "code", "spec", "status", "result", "error", "wall_time_s", "finished_at"}
        assert row["spec"] in (a, b)
        with pytest.raises(ValueError):
            st.put("k", a)
    with ResultStore(tmp_path / "r.sqlite") as st:  # reopens
        assert len(st) == 2 and st.meta()["schema_version"] == "2"


def test_garbage_file_raises_store_error_naming_the_path(tmp_path):
    p = tmp_path / "results.sqlite"
    p.write_bytes(b"\x00garbage" * 1000)
    with pytest.raises(StoreError, match=r"results\.sqlite"):
        ResultStore(p)


def test_other_sqlite_file_and_other_schema_version(tmp_path):
    p = tmp_path / "other.sqlite"
    db = sqlite3.connect(p)
    db.execute("CREATE TABLE t (x)")
    db.commit()
    db.close()
    with pytest.raises(StoreError, match="not a neurowalk result store"):
        ResultStore(p)
    q = tmp_path / "old.sqlite"
    ResultStore(q).close()
    db = sqlite3.connect(q)
    db.execute("UPDATE meta SET value = '0' WHERE name = 'schema_version'")
    db.commit()
    db.close()
    with pytest.raises(StoreError, match="schema version 0"):
        ResultStore(q)


def test_export_parquet_and_csv(tmp_path):
    with ResultStore(tmp_path / "r.sqlite") as st:
        for seed in range(3):
            s = _spec(seed)
            st.put(spec_key(s), s, result={"seed": seed, "x": seed / 2, "pose": [seed, 0], "ok": seed > 0})
        s = _spec(9)
        st.put(spec_key(s), s, error="RuntimeError: boom")
        tab = pq.read_table(st.export(tmp_path / "r.parquet", "parquet"))
        assert tab.num_rows == 4
        assert tab.column_names == [*EXPORT_META, *FIELDS, "x", "pose", "ok"]  # "seed" is a spec field already
        d = {r["seed"]: r for r in tab.to_pylist()}
        assert d[2]["x"] == 1.0 and d[2]["pose"] == "[2, 0]" and d[2]["ok"] is True
        assert d[9]["status"] == "error" and d[9]["x"] is None and d[9]["error"] == "RuntimeError: boom"
        assert d[0]["arena_opts"].startswith("{") and d[0]["steps"] == 30
        with open(st.export(tmp_path / "r.csv", "csv")) as f:
            rows = list(csv.DictReader(f))
        assert len(rows) == 4 and list(rows[0]) == tab.column_names
        with pytest.raises(ValueError, match="xls"):
            st.export(tmp_path / "r.xls", "xls")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["r.csv", "r.parquet", "r.sqlite", "r.sqlite.lock"]  # no temps


def test_export_names_the_defaults_a_stored_spec_leaves_out(tmp_path):
    plain, climbing = (
        _spec(0),
        EpisodeConfig.from_spec({"seed": 1, "steps": 30, "reflexes": True, "gait": "tripod"}).spec(),
    )
    assert not {"variant", "gait", "engine", "reflexes", "backbone", "body_opts"} & set(plain)  # left out
    with ResultStore(tmp_path / "r.sqlite") as st:
        for s in (plain, climbing):
            st.put(spec_key(s), s, result={"coverage": 0.5})
        with open(st.export(tmp_path / "r.csv", "csv")) as f:
            rows = {r["seed"]: r for r in csv.DictReader(f)}
        tab = {r["seed"]: r for r in pq.read_table(st.export(tmp_path / "r.parquet", "parquet")).to_pylist()}
    want = {"variant": "paper", "gait": "wave", "engine": "mujoco", "reflexes": "False", "backbone": "False",
            "body_opts": "{}", "controller": "plastic", "body": "amosii"}  # fmt: skip
    assert {k: rows["0"][k] for k in want} == want
    assert rows["1"]["gait"] == "tripod" and rows["1"]["reflexes"] == "True" and rows["1"]["variant"] == "paper"
    assert rows["0"]["params"] == rows["0"]["steer"] == ""  # none given: nothing to name
    assert tab[0]["reflexes"] is False and tab[1]["reflexes"] is True and tab[0]["engine"] == "mujoco"


def test_a_second_writer_of_one_store_is_refused_until_the_first_closes(tmp_path):
    with ResultStore(tmp_path / "r.sqlite"), pytest.raises(StoreError, match="in use by another sweep or figure"):
        ResultStore(tmp_path / "r.sqlite")
    with ResultStore(tmp_path / "r.sqlite") as st:  # released on close
        assert st.counts() is not None
