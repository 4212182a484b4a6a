"""`compare` returns the rows of runs.csv, as the binary writes them."""

import csv

import packbench

FIELDS = ["method", "seed", "d", "n", "phi", "z_nonrattler", "rattlers", "iso_gap", "isostatic",
          "max_overlap", "force_balance", "runtime_s", "steps", "termination"]


def test_rows_have_the_fields_of_runs_csv_and_its_values(cli, tmp_path):
    rows = packbench.compare(["adam", "ls"], n=30, dim=2, seeds=2, seed=4, jobs=1)
    assert [(r["method"], r["seed"]) for r in rows] == [("adam", 4), ("ls", 4), ("adam", 5), ("ls", 5)]
    out = cli("compare", "--methods", "adam,ls", "--N", 30, "--Ndim", 2, "--seeds", 2, "--seed", 4,
              "--jobs", 1, "--out", "cmp", "--quiet")
    assert out.returncode == 0, out.stderr
    with open(tmp_path / "cmp" / "runs.csv", newline="") as f:
        table = list(csv.DictReader(f))
    assert list(table[0])[: len(FIELDS)] == FIELDS
    assert set(rows[0]) == set(table[0])
    assert len(table) == len(rows)
    for row, line in zip(rows, table):
        assert row["method"] == line["method"] and str(row["seed"]) == line["seed"]
        assert repr(row["phi"]) == line["phi"] or float(line["phi"]) == row["phi"]
        assert row["steps"] == int(line["steps"])
        assert row["termination"] == line["termination"]


def test_refine_and_parameters():
    rows = packbench.compare("ls", n=20, dim=2, seeds=1, refine="closest-jammed",
                             params={"ls": {"rate": 0.5}}, dist="bidisperse", d1=1.0, d2=1.4, p=0.5)
    (row,) = rows
    assert row["refined_phi"] is not None and row["delta_phi"] is not None
    assert row["refined_phi"] >= row["phi"] - 1e-9
    assert row["refined_by"] == "closest-jammed"


def test_refine_exact_is_calippso_at_small_n():
    """refine="exact" at small N is calippso directly, named in the row, exactly jammed."""
    (row,) = packbench.compare("adam", n=30, dim=2, seeds=1, refine="exact")
    assert row["refined_by"] == "calippso"
    assert row["refined_termination"] == "converged"
    assert row["refined_iso_gap"] == 0
    assert row["refined_force_balance"] < 1e-9
    assert row["refined_runtime_s"] > 0
