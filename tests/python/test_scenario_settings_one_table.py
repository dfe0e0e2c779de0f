"""One table of the cosim scenario's settings (stcosim/scenario_settings.hpp), two front ends: every
key the table lists is accepted by the scenario YAML and by `stsim highway`'s options (--set, and
the option that stands for it: --end, --seed, ...), lands as the same value (read back through
`stsim highway --scenario-settings`), and a value out of its range, of another type or not among
its words is refused by both with the same one-line words, naming the file and line or the option.
docs/scenario_settings.md is the table as `stsim highway --scenario-settings` prints it."""
import re

from conftest import SOURCE, doc_table, run_stsim, scenario_yaml, setting_text as as_text, settings_rows

SUMOCFG = SOURCE / "networks" / "motorway" / "motorway.sumocfg"
# the options that stand for one key (app/src/highway_command.cpp kRunOptions)
OPTIONS = {"penetration": "--penetration", "action": "--action", "end": "--end", "demand_scale": "--scale",
           "seed": "--seed"}


def reference(binary, *args):
    return settings_rows(binary, "--scenario-settings", *args)


def values(row):
    """A valid value other than the default, and the values the table refuses, as text."""
    v, default = row["value"], row["current"]
    if v == "true or false":
        return as_text(default != "true"), ["maybe"]
    if v.startswith("one of "):
        words = v[len("one of "):].split(", ")
        return next(w for w in words if w != default), ["nonsense"]
    m = re.search(r"in [\[(]([^,]+), ([^\]]+)\]", v)
    lo, hi = float(m.group(1)), float(m.group(2))
    good = lo + 0.375 * (min(hi, lo + 100.0) - lo)
    if v.startswith("whole number"):
        good = float(round(good))
    bad = [as_text(hi * 2.0 + 1.0), "ten"]
    if v.startswith(("number in (", "whole number in (")):
        bad.append(as_text(lo))  # the range's lower end, excluded
    elif lo > 0.0:
        bad.append(as_text(lo / 2.0))
    bad.append(as_text(lo - 1.0))
    return as_text(good), bad


def yaml_text(key, value):
    return scenario_yaml(key, value)


def test_docs_are_the_table(stsim_binary):
    _, printed = reference(stsim_binary)
    assert doc_table("scenario_settings.md") == printed, "docs/scenario_settings.md differs from `stsim highway --scenario-settings`: regenerate it"


def test_every_key_is_accepted_and_refused_alike_in_yaml_and_on_the_command_line(stsim_binary, tmp_path):
    rows, _ = reference(stsim_binary)
    assert {"seed", "end", "penetration", "action", "collision_action", "brake.deceleration"} <= set(rows)
    scenario = tmp_path / "s.yaml"
    for key, row in rows.items():
        good, bad = values(row)
        given = [("--set", f"{key}={good}")] + ([(OPTIONS[key], good)] if key in OPTIONS else [])
        text, _ = yaml_text(key, good)
        scenario.write_text(text)
        assert reference(stsim_binary, scenario)[0][key]["current"] == good, key
        for option, value in given:
            assert reference(stsim_binary, option, value)[0][key]["current"] == good, (key, option)
        # a number key's word ("sumocfg": the sumocfg's end) is a value like any other
        word = re.search(r", or (\w+)$", row["value"])
        if word:
            scenario.write_text(yaml_text(key, word.group(1))[0])
            assert reference(stsim_binary, scenario, "--set", f"{key}={good}")[0][key]["current"] == good, key
            assert reference(stsim_binary, "--set", f"{key}={word.group(1)}")[0][key]["current"] == word.group(1), key
        for value in bad:
            text, line = yaml_text(key, value)
            scenario.write_text(text)
            y = run_stsim(stsim_binary, "highway", scenario, "--scenario-settings")
            assert y.returncode == 1, (key, value, y.stderr)
            prefix = f"stsim highway: error: {scenario}:{line}: {key}: "
            assert y.stderr.startswith(prefix) and y.stderr.count("\n") == 1, (key, value, y.stderr)
            problem = y.stderr[len(prefix):]
            option_values = [("--set", f"{key}={value}", f"--set {key}")]
            if key in OPTIONS:
                option_values.append((OPTIONS[key], value, OPTIONS[key]))
            for option, arg, named in option_values:
                c = run_stsim(stsim_binary, "highway", "--scenario-settings", option, arg)
                assert c.returncode == 2, (key, value, c.stderr)
                assert c.stderr == f"stsim highway: {named}: {problem}", (key, value, c.stderr, problem)


def test_a_pair_of_keys_is_checked_alike(stsim_binary, tmp_path):
    # what no single key checks: the hardest braking against the braking it starts with
    scenario = tmp_path / "s.yaml"
    scenario.write_text(f"sumocfg: {SUMOCFG}\nbrake: {{deceleration: 10}}\n")
    y = run_stsim(stsim_binary, "highway", scenario, "--scenario-settings")
    assert y.stderr == f"stsim highway: error: {scenario}:2: brake.max_deceleration: must be at least brake.deceleration\n"
    c = run_stsim(stsim_binary, "highway", "--scenario-settings", "--set", "brake.deceleration=10")
    assert c.stderr == "stsim highway: --set brake.max_deceleration: must be at least brake.deceleration\n"
