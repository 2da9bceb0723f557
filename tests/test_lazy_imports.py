"""`import setsmooth` is cheap: the public names load their modules on first use."""

import subprocess
import sys

import pytest

import setsmooth as ss


def _run(code: str) -> str:
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout


def test_importing_the_package_and_the_command_line_loads_no_solver():
    out = _run("import sys, setsmooth, setsmooth.runs.cli; "
               "print(sorted(m for m in ('cvxpy', 'clarabel', 'scipy', 'matplotlib') if m in sys.modules))")
    assert out.strip() == "[]"


def test_every_public_name_resolves_to_its_defining_object():
    from setsmooth.sets.box import Box
    from setsmooth.trajectories import trajectory_set

    assert all(hasattr(ss, name) for name in ss.__all__)
    assert ss.Box is Box and ss.trajectory_set is trajectory_set
    assert ss.montecarlo.__name__ == "setsmooth.runs.montecarlo"
    namespace: dict = {}
    exec("from setsmooth import *", namespace)
    assert set(ss.__all__) <= set(namespace)


def test_an_unknown_name_is_an_attribute_error():
    with pytest.raises(AttributeError, match="no_such_name"):
        ss.no_such_name


def test_the_core_never_imports_dask():
    out = _run("import sys, numpy as np, setsmooth as ss, setsmooth.runs.cli\n"
               "from setsmooth.runs.montecarlo import run\n"
               "run(np.random.Generator.random, 3, seed=0, executor='serial', progress=False)\n"
               "ss.classical_filter; ss.optimal_smoother; ss.Box([0], [1]).interval_hull()\n"
               "print(sorted(m for m in ('dask', 'distributed') if m in sys.modules))")
    assert out.strip() == "[]"


def test_python_m_setsmooth_runs_the_command_line():
    out = subprocess.run([sys.executable, "-m", "setsmooth", "figures", "--list"], capture_output=True,
                         text=True, check=True).stdout
    assert "smoothing_fig3" in out.split()
