"""scripts/check_safety_trace.py: the hazard table's tests must exist and pass in the run."""

from __future__ import annotations

import importlib.util
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
spec = importlib.util.spec_from_file_location("check_safety_trace", ROOT / "scripts" / "check_safety_trace.py")
assert spec and spec.loader
trace = importlib.util.module_from_spec(spec)
sys.modules[spec.name] = trace  # dataclasses look their module up
spec.loader.exec_module(trace)

UNIT = "crates/haptic-wheel/src/safety.rs::nan_request_ramps_to_zero"
INTEGRATION = "crates/assist/tests/safety.rs::torque_is_finite_within_ceiling_and_slew_for_any_input"
WORKSPACE = "tests/session_e2e.rs::sigint_ends_the_session_cleanly_with_a_readable_recording"
PYTHON = "tests/python/test_check_skips.py::test_the_allow_list_has_only_the_uinput_reason"

GOOD_LOG = """\
     Running unittests src/lib.rs (target/debug/deps/haptic_wheel-0123abcd)
running 2 tests
test safety::tests::nan_request_ramps_to_zero ... ok
     Running tests/safety.rs (target/debug/deps/safety-89ab01cd)
some output of a test without its newline test torque_is_finite_within_ceiling_and_slew_for_any_input ... ok
     Running session_e2e.rs (target/debug/deps/session_e2e-feed0123)
test sigint_ends_the_session_cleanly_with_a_readable_recording ... ok
"""

GOOD_XML = """<?xml version="1.0"?><testsuites><testsuite>
<testcase classname="tests.python.test_check_skips" name="test_the_allow_list_has_only_the_uinput_reason" time="0.1"/>
</testsuite></testsuites>"""


def table(tmp_path: pathlib.Path, *entries: str) -> pathlib.Path:
    path = tmp_path / "hazards.md"
    path.write_text("| H | tests |\n" + "".join(f"| x | `{e}` |\n" for e in entries), encoding="utf-8")
    return path


def problems(tmp_path, entries, log=GOOD_LOG, xml=GOOD_XML):
    return trace.check([table(tmp_path, *entries)], log, xml, exists_only=False)


def test_tests_that_exist_and_passed_in_their_own_binary_keep_the_trace(tmp_path) -> None:
    assert problems(tmp_path, [UNIT, INTEGRATION, WORKSPACE, PYTHON]) == []


def test_a_renamed_test_or_a_missing_file_breaks_the_trace(tmp_path) -> None:
    found = problems(tmp_path, [UNIT + "_renamed", "crates/assist/tests/nowhere.rs::x"])
    assert len(found) == 2
    assert "defines no `fn nan_request_ramps_to_zero_renamed`" in found[0]
    assert "does not exist" in found[1]


def test_a_failed_ignored_or_unrun_test_breaks_the_trace(tmp_path) -> None:
    failed = GOOD_LOG.replace("nan_request_ramps_to_zero ... ok", "nan_request_ramps_to_zero ... FAILED")
    assert "FAILED" in problems(tmp_path, [UNIT], log=failed)[0]
    ignored = GOOD_LOG.replace("nan_request_ramps_to_zero ... ok", "nan_request_ramps_to_zero ... ignored")
    assert "ignored" in problems(tmp_path, [UNIT], log=ignored)[0]
    unrun = GOOD_LOG.replace("test sigint_ends", "# sigint_ends")
    assert "did not run" in problems(tmp_path, [WORKSPACE], log=unrun)[0]


def test_a_test_of_the_same_name_in_another_crates_binary_does_not_count(tmp_path) -> None:
    elsewhere = GOOD_LOG.replace("deps/haptic_wheel-0123abcd", "deps/assist-0123abcd")
    assert "did not run" in problems(tmp_path, [UNIT], log=elsewhere)[0]


def test_a_skipped_or_failed_python_test_breaks_the_trace(tmp_path) -> None:
    skipped = GOOD_XML.replace('time="0.1"/>', 'time="0.1"><skipped message="no display"/></testcase>')
    assert "skipped" in problems(tmp_path, [PYTHON], xml=skipped)[0]
    failed = GOOD_XML.replace('time="0.1"/>', 'time="0.1"><failure message="x"/></testcase>')
    assert "failure" in problems(tmp_path, [PYTHON], xml=failed)[0]


def test_every_test_the_shipped_hazard_table_names_exists() -> None:
    assert trace.check(trace.DEFAULT_TABLES, None, None, exists_only=True) == []


def test_a_test_run_once_a_backend_and_a_module_named_from_its_folder_keep_the_trace(tmp_path) -> None:
    """The hub's tests run once on SQLite and once on PostgreSQL (`name::sqlite`,
    `name::postgres`); pytest may name a module from the test folder (`test_check_skips`).
    Both count; a failure on either backend breaks the trace."""
    both = "crates/hub/tests/db.rs::concurrent_duplicates_are_stored_once"
    log = GOOD_LOG + (
        "     Running tests/db.rs (target/debug/deps/db-0123abcd)\n"
        "test concurrent_duplicates_are_stored_once::sqlite ... ok\n"
        "test concurrent_duplicates_are_stored_once::postgres ... ok\n"
    )
    short = GOOD_XML.replace('classname="tests.python.test_check_skips"', 'classname="test_check_skips"')
    assert problems(tmp_path, [both, PYTHON], log=log, xml=short) == []
    one_failed = log.replace("once::postgres ... ok", "once::postgres ... FAILED")
    assert "FAILED" in problems(tmp_path, [both], log=one_failed)[0]
    other = GOOD_XML.replace('classname="tests.python.test_check_skips"', 'classname="test_elsewhere"')
    assert "did not run" in problems(tmp_path, [PYTHON], xml=other)[0]


def test_a_result_another_tests_output_pushed_off_its_line_takes_its_binarys_summary(tmp_path) -> None:
    """With `--nocapture`, a parallel test's output can land between `test name ...` and its
    `ok`: the binary's `test result: ok … 0 failed` then says it passed; a binary that failed
    leaves it unproven."""
    interleaved = GOOD_LOG.replace(
        "test safety::tests::nan_request_ramps_to_zero ... ok\n",
        "test safety::tests::nan_request_ramps_to_zero ... other test: 0 allocations in 3700 ticks\n"
        "ok\n"
        "test result: ok. 2 passed; 0 failed; 0 ignored; 0 measured; 0 filtered out; finished in 0.1s\n")
    assert problems(tmp_path, [UNIT], log=interleaved) == []
    failed = interleaved.replace("test result: ok. 2 passed; 0 failed", "test result: FAILED. 1 passed; 1 failed")
    assert "FAILED" in problems(tmp_path, [UNIT], log=failed)[0]
    unfinished = interleaved.replace("test result: ok. 2 passed; 0 failed; 0 ignored; 0 measured; 0 filtered out; finished in 0.1s\n", "")
    assert "did not run" in problems(tmp_path, [UNIT], log=unfinished)[0]
