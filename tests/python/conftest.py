import os
import pathlib
import subprocess

import pytest

SOURCE = pathlib.Path(os.environ.get("STSIM_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
DATA = SOURCE / "tests" / "data" / "highway"


@pytest.fixture(scope="session")
def stsim_binary():
    b = os.environ.get("STSIM_BINARY")
    if not b or not os.path.exists(b):
        pytest.skip("STSIM_BINARY not set (ctest sets it)")
    return b


def run_stsim(binary, *args, cwd=None):
    return subprocess.run([binary, *map(str, args)], cwd=cwd, capture_output=True, text=True, timeout=300)


def settings_rows(binary, flag, *args):
    """`stsim highway FLAG ARGS` (--settings, --scenario-settings) as {key: {value, current}} and
    the text printed."""
    r = run_stsim(binary, "highway", flag, *args)
    assert r.returncode == 0, r.stderr
    rows = {}
    for line in r.stdout.splitlines()[2:]:
        cells = [c.strip() for c in line.strip("|").split("|")]
        rows[cells[0].strip("`")] = {"value": cells[1], "current": cells[2]}
    return rows, r.stdout


def setting_text(x):
    """A value as the settings tables print it (numbers to 15 digits)."""
    if isinstance(x, bool):
        return "true" if x else "false"
    if isinstance(x, float):
        return f"{x:.15g}"
    return str(x)


def scenario_yaml(key, value):
    """A motorway scenario giving one nested key ("brake.deceleration") the text value, and the
    line that gives it."""
    parts = key.split(".")
    lines = [f"sumocfg: {SOURCE / 'networks' / 'motorway' / 'motorway.sumocfg'}"]
    for depth, p in enumerate(parts[:-1]):
        lines.append("  " * depth + p + ":")
    lines.append("  " * (len(parts) - 1) + f"{parts[-1]}: {value}")
    return "\n".join(lines) + "\n", len(lines)


def doc_table(name):
    """The Markdown table rows of docs/NAME, as a command prints them."""
    doc = (SOURCE / "docs" / name).read_text()
    return "\n".join(line for line in doc.splitlines() if line.startswith("|")) + "\n"
