"""pytest set-up for the Python module's tests (ctest runs them: tests/CMakeLists.txt).

HYFAL_PYTHON_DIR: the folder holding the built module (<build>/python); HYFAL_CLI: the `hyfal`
binary of the same build, for the tests that compare with the command line (skipped without it).
Run by hand:
    HYFAL_PYTHON_DIR=build/python HYFAL_CLI=build/app/hyfal /usr/bin/python3 -m pytest tests/python
"""
import os
import sys

import pytest

_here = os.path.dirname(os.path.abspath(__file__))
_root = os.path.dirname(os.path.dirname(_here))
_module_dir = os.environ.get("HYFAL_PYTHON_DIR") or os.path.join(_root, "build", "python")
sys.path.insert(0, os.path.abspath(_module_dir))
sys.path.insert(0, _here)  # stl_reference


@pytest.fixture(scope="session")
def hyfal_cli():
    """The hyfal binary (HYFAL_CLI), or skip."""
    path = os.environ.get("HYFAL_CLI")
    if not path or not os.access(path, os.X_OK):
        pytest.skip("HYFAL_CLI is not set to the hyfal binary")
    return path
