"""Examples that are part of the API contract: a python-control user's script runs as written."""

import os
import subprocess
import sys
from pathlib import Path

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def test_python_control_quickstart_fits_in_25_lines_and_finds_the_sensor_fault():
    script = EXAMPLES / "python_control_quickstart.py"
    assert len(script.read_text(encoding="utf-8").splitlines()) <= 25
    env = dict(os.environ, MPLBACKEND="Agg", OPENBLAS_NUM_THREADS="1")
    done = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, env=env,
                          timeout=600, check=True)
    assert "data consistent with the model: True" in done.stdout
    assert "drifting sensor caught at k = 25" in done.stdout
    assert (EXAMPLES / "out" / "python_control_quickstart.png").stat().st_size > 0
