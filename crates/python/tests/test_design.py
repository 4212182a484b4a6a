"""`design` runs the search of `packbench design` and returns its rows and best distribution:
a known answer, the same rows from the same seed (and from the binary), bad input refused."""

import csv

import numpy as np
import pytest

import packbench

# Bidisperse spheres at equal numbers with the size ratio between 1 and 1.4: φ_J rises with
# the ratio, so the best candidate sits at the upper bound (cli_design.rs's bound test).
BIDISPERSE = dict(bounds={"ratio": (1.0, 1.4), "p": 0.5}, n=128, dim=3)

# A short search: 2 generations of 4 candidates × 1 seed, 2 confirmations, N = 48.
SHORT = dict(n=48, dim=3, seeds_per_candidate=1, budget=8, confirm=2, screen="none", jobs=2)


def without_runtime(rows):
    return [{k: v for k, v in r.items() if k != "runtime_s"} for r in rows]


def test_bidisperse_best_sits_at_the_upper_ratio_bound():
    # 64 packings: room for IPOP's restarts and the incumbent's re-evaluations, as the CLI test.
    result = packbench.design("bidisperse", **BIDISPERSE, seeds_per_candidate=2, budget=64,
                              confirm=2, jobs=2)
    best = result["best"]
    assert best["names"] == ["ratio", "p"]
    # Within 2.5 % of the span from the bound: at N = 128 a candidate's φ_J scatters by ~0.003,
    # more than φ_J gains over the last hundredth of the ratio.
    assert 1.39 <= best["params"]["ratio"] <= 1.4, best
    assert best["params"]["p"] == 0.5
    assert isinstance(best["diameters"], np.ndarray) and best["diameters"].shape == (128,)
    assert set(np.unique(best["diameters"])) <= {1.0, best["params"]["ratio"]}
    assert len(best["confirm_phi"]) == 2
    assert best["confirm_mean"] == pytest.approx(np.mean(best["confirm_phi"]))
    assert 0.6 < best["confirm_mean"] < 0.7
    # The standard deviation of the two confirmations, recomputed here (sample, ddof = 1).
    assert best["confirm_std"] == pytest.approx(np.std(best["confirm_phi"], ddof=1), abs=1e-12)
    assert result["packings"] <= 64
    search = [r for r in result["rows"] if r["kind"] == "search" and not r["screened"]]
    assert len(search) == result["packings"]
    assert sum(r["kind"] == "confirm" for r in result["rows"]) == 2


def test_discrete_mixture_searched_at_a_smaller_n_and_confirmed_at_n():
    result = packbench.design("discrete", components=2, max_ratio=3.0, search_n=32,
                              max_rattlers=0.5, **{**SHORT, "n": 48, "confirm": 1})
    best = result["best"]
    assert best["names"] == ["d2", "x1"]
    assert 1.0 <= best["params"]["d2"] <= 3.0 and 0.0 <= best["params"]["x1"] <= 1.0
    # Two sizes only, N of the confirmation.
    assert best["diameters"].shape == (48,)
    assert set(np.unique(best["diameters"])) <= {1.0, best["params"]["d2"]}
    packed = [r for r in result["rows"] if r["kind"] == "search" and not r["screened"]]
    assert packed and all(r["n"] == 32 for r in packed)
    assert [r["n"] for r in result["rows"] if r["kind"] == "confirm"] == [48]


def test_quantile_draws_pack_the_distributions_quantiles():
    # draw="quantile" (the default): the best's N diameters are exp(σ Φ⁻¹((i + ½)/N)), with
    # Φ⁻¹ from Python's own statistics module; draw="random" draws them, so ln D is not
    # symmetric about 0.
    from statistics import NormalDist

    bounds = {"sigma": (0.1, 0.3)}
    best = packbench.design("lognormal", bounds=bounds, **SHORT)["best"]
    z = np.array([NormalDist().inv_cdf((i + 0.5) / 48) for i in range(48)])
    ln = np.sort(np.log(best["diameters"]))
    np.testing.assert_allclose(ln, best["params"]["sigma"] * z, rtol=1e-9, atol=1e-12)
    drawn = packbench.design("lognormal", bounds=bounds, draw="random", **SHORT)["best"]
    assert abs(np.log(drawn["diameters"]).mean()) > 1e-6


def test_same_seed_same_rows_as_the_binary(cli, tmp_path):
    a = packbench.design("lognormal", **SHORT)
    b = packbench.design("lognormal", **SHORT)
    c = packbench.design("lognormal", **SHORT, seed=5)
    assert len(a["rows"]) == 8 + 2
    assert without_runtime(a["rows"]) == without_runtime(b["rows"])
    assert without_runtime(a["rows"]) != without_runtime(c["rows"])
    assert a["best"]["values"] == b["best"]["values"]
    out = cli("design", "--family", "lognormal", "--N", 48, "--Ndim", 3,
              "--seeds-per-candidate", 1, "--budget", 8, "--confirm", 2, "--screen", "none",
              "--jobs", 2, "--out", "d", "--quiet")
    assert out.returncode == 0, out.stderr
    with open(tmp_path / "d" / "evaluations.csv", newline="") as f:
        table = list(csv.DictReader(f))
    assert len(table) == len(a["rows"])
    assert list(a["rows"][0]) == list(table[0])
    for row, line in zip(a["rows"], table):
        assert (row["kind"], row["generation"], row["candidate"], row["seed"]) == (
            line["kind"], int(line["generation"]), int(line["candidate"]), int(line["seed"]))
        assert float(line["sigma"]) == row["sigma"]
        assert (float(line["phi"]) if line["phi"] else None) == row["phi"]


@pytest.mark.parametrize(
    "keywords, says",
    [
        (dict(family="cauchy"), "unknown family"),
        (dict(family="lognormal", bounds={"mu": (0, 1)}), "no parameter `mu`"),
        (dict(family="bidisperse", bounds={"ratio": (1.4, 1.0)}), "reversed"),
        (dict(family="bidisperse", bounds={"ratio": 1.4, "p": 0.5}), "every parameter fixed"),
        (dict(family="lognormal", bounds={"sigma": (0, 1, 2)}), "pair (lo, hi)"),
        (dict(family="lognormal", objective="target", target=1.3), "target=1.3 is impossible"),
        (dict(family="lognormal", objective="target"), "needs target="),
        (dict(family="lognormal", objective="densest"), "unknown objective"),
        (dict(family="mixture", components=0), "components=0"),
        (dict(family="lognormal", budget=2), "budget=2 is too small"),
        (dict(family="lognormal", method="nope"), "nope"),
        (dict(family="lognormal", n=-3), "n=-3"),
        (dict(family=3), "family must be a name"),
        (dict(family="discrete", fractions="mass"), 'fractions="mass"'),
        (dict(family="lognormal", draw="sorted"), 'draw="sorted"'),
        (dict(family="bidisperse", optimizer="bracket"), "optimizer=\"bracket\" searches one"),
        (dict(family="lognormal", optimizer="simplex"), "unknown optimizer"),
        (dict(family="lognormal", max_rattlers=2.0), "max_rattlers=2"),
    ],
)
def test_bad_input_raises_value_error_naming_the_keyword(keywords, says):
    with pytest.raises(ValueError) as e:
        packbench.design(**{"n": 48, "dim": 3, **keywords})
    assert says in str(e.value)
    assert "--" not in str(e.value)
