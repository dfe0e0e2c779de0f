"""One table of monitor settings (sthighway/settings.hpp), three front ends: every key the table
lists is accepted by the YAML scenario, by `stsim highway --set` and by Python's Monitor(**kw),
lands as the same value (read back through `stsim highway --settings` and Monitor.settings), and a
value out of its range or choices is refused by all three with the same words. docs/settings.md
is the table as `stsim highway --settings` prints it."""
import re

import pytest

import stsim
from conftest import doc_table, run_stsim, scenario_yaml, setting_text as as_text, settings_rows


def reference(binary, *args):
    return settings_rows(binary, "--settings", *args)


def parse_range(value):
    m = re.search(r"in \[([^,]+), ([^\]]+)\]", value)
    return (float(m.group(1)), float(m.group(2))) if m else None


def good_and_bad(row, default):
    """A valid value other than the default, and one the table refuses (None for booleans)."""
    v = row["value"]
    if v == "true or false":
        return (default != "true"), None
    if v.startswith("one of "):
        words = v[len("one of "):].split(", ")
        return next(w for w in words if w != default), "nonsense"
    lo, hi = parse_range(v)
    good = lo + 0.375 * (min(hi, lo + 100.0) - lo)
    if v.startswith("whole number"):
        good = float(round(good))
        if str(int(good)) == default:
            good += 1.0
    return good, hi * 2.0 + 1.0


def nested(key, value):
    parts = key.split(".")
    out = value
    for p in reversed(parts[1:]):
        out = {p: out}
    return parts[0], out


def yaml_text(key, value):
    return scenario_yaml(key, as_text(value))[0]


def test_docs_are_the_table(stsim_binary):
    _, printed = reference(stsim_binary)
    assert doc_table("settings.md") == printed, "docs/settings.md differs from `stsim highway --settings`: regenerate it"


def test_every_key_means_the_same_and_is_refused_alike_in_yaml_cli_and_python(stsim_binary, tmp_path):
    rows, _ = reference(stsim_binary)
    assert len(rows) > 30
    defaults = stsim.Monitor().settings
    assert set(defaults) == set(rows)
    for key, row in rows.items():
        assert as_text(defaults[key]) == row["current"], key
        good, bad = good_and_bad(row, row["current"])
        # Python: the flat spelling and the nested dicts
        assert as_text(stsim.Monitor(**{key.replace(".", "_"): good}).settings[key]) == as_text(good), key
        top, inner = nested(key, good)
        assert as_text(stsim.Monitor(**{top: inner}).settings[key]) == as_text(good), key
        # the YAML scenario and the command line, read back as the run would use them
        scenario = tmp_path / "s.yaml"
        scenario.write_text(yaml_text(key, good))
        from_yaml, _ = reference(stsim_binary, scenario)
        assert from_yaml[key]["current"] == as_text(good), key
        from_cli, _ = reference(stsim_binary, "--set", f"{key}={as_text(good)}")
        assert from_cli[key]["current"] == as_text(good), key
        # refused alike
        scenario.write_text(yaml_text(key, bad if bad is not None else "maybe"))
        y = run_stsim(stsim_binary, "highway", scenario, "--settings")
        c = run_stsim(stsim_binary, "highway", "--settings", "--set", f"{key}={as_text(bad) if bad is not None else 'maybe'}")
        assert y.returncode != 0 and key in y.stderr, (key, y.stderr)
        assert c.returncode == 2 and key in c.stderr, (key, c.stderr)
        with pytest.raises((ValueError, TypeError)) as py_error:
            stsim.Monitor(**{key.replace(".", "_"): bad if bad is not None else "maybe"})
        assert key in str(py_error.value)
        if bad is not None:
            problem = c.stderr.split(f"{key}: ", 1)[1].strip()
            assert problem in y.stderr, (key, problem, y.stderr)
            assert problem in str(py_error.value), (key, problem, str(py_error.value))
