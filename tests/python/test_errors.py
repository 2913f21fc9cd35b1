"""hyfal's errors in Python (core/util/error.hpp, python/module.cpp): every C++ error type reaches
Python as its own class, beneath hyfal.InputError (a ValueError) or hyfal.EnvironmentError (an
OSError), and the classes the module's calls raise are those."""
import numpy as np
import pytest

import hyfal

INPUT = ["OptionError", "RequirementError", "WitnessError", "ExperimentFileError", "UsageError",
         "MethodNotApplicable", "StoreInputError", "ClusterSetupError"]
ENVIRONMENT = ["StoreEnvironmentError", "ClusterFailure"]


def test_the_hierarchy():
    assert issubclass(hyfal.InputError, ValueError)
    assert issubclass(hyfal.EnvironmentError, OSError)
    for name in INPUT:
        assert issubclass(getattr(hyfal, name), hyfal.InputError), name
        assert not issubclass(getattr(hyfal, name), OSError), name
    for name in ENVIRONMENT:
        assert issubclass(getattr(hyfal, name), hyfal.EnvironmentError), name
    assert issubclass(hyfal.MethodNotApplicable, hyfal.UsageError)
    for name in ["StoreInputError", "StoreEnvironmentError"]:
        assert issubclass(getattr(hyfal, name), hyfal.StoreError)
    for name in ["ClusterSetupError", "ClusterFailure"]:
        assert issubclass(getattr(hyfal, name), hyfal.ClusterError)
    assert hyfal.OptionError.__module__ == "hyfal" and hyfal.OptionError.__doc__


@pytest.mark.parametrize("name", ["InputError", "EnvironmentError"] + INPUT + ENVIRONMENT)
def test_every_cpp_error_arrives_as_its_own_class(name):
    with pytest.raises(getattr(hyfal, name)) as e:
        hyfal._raise_error(name, "what went wrong")
    assert type(e.value) is getattr(hyfal, name)
    assert "what went wrong" in str(e.value)
    if name == "RequirementError":
        assert e.value.column == 7
    if name.startswith("Store"):
        assert e.value.sqlite_code == (26 if name == "StoreInputError" else 13)


def test_a_bug_is_not_disguised_as_an_input_error():
    with pytest.raises(RuntimeError, match="no hyfal error is called Nope") as e:
        hyfal._raise_error("Nope", "x")
    assert not isinstance(e.value, ValueError)


def test_the_calls_raise_the_classes(tmp_path):
    with pytest.raises(hyfal.RequirementError) as e:
        hyfal.falsify(suite="at", requirement="always[0,1 y1 < 2")
    assert e.value.column > 0 and str(e.value).startswith("requirement: column")
    with pytest.raises(hyfal.OptionError, match="budget"):
        hyfal.falsify(suite="at", requirement="AT2", method="random", budget="many")
    with pytest.raises(hyfal.UsageError, match="experiment"):
        hyfal.falsify(suite="at", requirement="AT2", experiment="../x")
    with pytest.raises(hyfal.MethodNotApplicable, match="use rrft"):
        hyfal.falsify(suite="f16", requirement="F16", method="rrt")
    junk = tmp_path / "junk.sqlite"
    junk.write_text("not a database\n")
    with pytest.raises(hyfal.StoreInputError, match="junk.sqlite") as e:
        hyfal.read_results(str(junk))
    assert isinstance(e.value, hyfal.StoreError) and e.value.sqlite_code == 0  # found by hyfal, not SQLite
