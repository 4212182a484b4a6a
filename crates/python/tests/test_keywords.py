"""Every bad keyword value is a ValueError that names the keyword the user typed, and the
library's sentences speak of keywords, not of the command line's flags."""

import pytest

import packbench


@pytest.mark.parametrize("call, keyword", [
    (lambda: packbench.initial_packing(-3, 2), "n=-3"),
    (lambda: packbench.initial_packing(10, 2, seed=-1), "seed=-1"),
    (lambda: packbench.initial_packing(10, 1), "dim=1"),
    (lambda: packbench.initial_packing(10.5, 2), "n=10.5"),
    (lambda: packbench.initial_packing(True, 2), "n=True"),
    (lambda: packbench.pack("adam", packbench.initial_packing(10, 2), seed=-2), "seed=-2"),
    (lambda: packbench.pack("adam", packbench.initial_packing(10, 2), max_steps=0), "max_steps=0"),
    (lambda: packbench.compare("adam", n=-5, dim=2), "n=-5"),
    (lambda: packbench.compare("adam", n=10, dim=2, seeds=0), "seeds=0"),
    (lambda: packbench.compare("adam", n=10, dim=2, jobs=0), "jobs=0"),
    (lambda: packbench.initial_packing(10, 2, phi="dense"), "phi='dense'"),
    (lambda: packbench.compare("adam", n=10, dim=2, phi=[0.1]), "phi=[0.1]"),
])
def test_negative_or_fractional_integers_are_value_errors_naming_the_keyword(call, keyword):
    with pytest.raises(ValueError) as e:
        call()
    assert str(e.value).startswith(keyword), str(e.value)


def test_numpy_integers_are_whole_numbers():
    import numpy as np

    p = packbench.initial_packing(np.int64(12), np.int32(2), seed=np.uint8(3), phi=np.float32(0.1))
    assert p.n == 12 and p.dim == 2
    assert p == packbench.initial_packing(12, 2, seed=3, phi=float(np.float32(0.1)))


def test_a_dict_for_dist_is_a_value_error_that_shows_the_keywords():
    with pytest.raises(ValueError) as e:
        packbench.initial_packing(10, 2, dist={"name": "bidisperse", "d1": 1})
    assert "dist must be a name" in str(e.value) and 'dist="bidisperse", d1=' in str(e.value)
    with pytest.raises(ValueError, match="dist must be a name"):
        packbench.compare("adam", n=10, dim=2, dist=["mono"])
    with pytest.raises(ValueError, match="d1='big': d1 must be a number"):
        packbench.initial_packing(10, 2, dist="bidisperse", d1="big", d2=1.4, p=0.5)


def test_sentences_name_keywords_not_flags():
    with pytest.raises(ValueError) as e:
        packbench.initial_packing(10, 3, box=[1, 1])
    assert str(e.value).startswith("box= has 2 lengths"), str(e.value)
    with pytest.raises(ValueError) as e:
        packbench.initial_packing(10, 2, dist="biGaussian", mu1=1, sigma1=0.1, mu2=2, p=0.5)
    assert str(e.value) == 'dist="biGaussian" needs sigma2=', str(e.value)
    for message in [str(e.value)]:
        assert "--" not in message


def test_the_command_line_keeps_its_flags(cli):
    out = cli("init", "--N", 10, "--Ndim", 3, "--box", "1,1")
    assert out.returncode == 2 and "--box has 2 lengths" in out.stderr
