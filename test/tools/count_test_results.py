#!/usr/bin/env python3
"""Count passed and failed tests in the JUnit XML files under a results directory.

    count_test_results.py RESULTS_DIR        (e.g. .ws/build/test_results)

`catkin_make run_tests` exits 0 even when tests fail; this script is the gate. It walks RESULTS_DIR
recursively and reads every *.xml file once (files reached twice through symlinks, and byte-identical
copies, are counted once):

  gtest-*.xml     gtest output, <testsuites><testsuite><testcase .../>...
  rostest-*.xml   rostest's own record, <testsuite><testcase name="test<test-name>"/>: one wrapper
                  testcase per <test> node, failed when the node did not run or wrote no results
  rosunit-*.xml   the results written by each rostest test node (gtest or unittest style); a passed
                  wrapper testcase whose rosunit-<test-name>.xml exists is counted through that file
                  only, so a rostest with one test method counts once, not twice
  python-*.xml    test/python's modules, written by test/helpers/junit_unittest.py (unittest style)
  MISSING-*.xml   catkin's placeholder for a test that produced no results (one failed testcase)

A testcase with a <failure> or <error> child is failed; one with <skipped> (or gtest's
status="notrun" / result="skipped") is skipped; any other is passed. A <testsuite> that declares
more errors/failures than its failed testcases counts the difference as failed: a rostest that never
ran its test node (no testcase at all), or unittest subTest failures (rosunit counts them in the suite
but attaches them to no testcase); and an .xml file that is not well-formed counts as 1 failed. gtest's <testsuites> totals are not added on top of
its testcases (catkin_test_results adds both, so it reports every gtest twice).

Prints one line per file, "  FILE: X passed, Y failed", then the failed testcases (file, name and
the first line of the failure) so that a log's tail names them, and as the last line exactly
"N passed, M failed". Exit status 1 when M > 0 or N == 0, else 0.
"""
import hashlib
import os
import sys
import xml.etree.ElementTree as ET


def _int_attr(node, name):
    try:
        return int(float(node.get(name, "0")))
    except ValueError:
        return 0


def _testcase_outcome(case):
    """'failed', 'skipped' or 'passed' for one <testcase>."""
    children = {child.tag for child in case}
    if "failure" in children or "error" in children:
        return "failed"
    if "skipped" in children or case.get("status") == "notrun" or case.get("result") == "skipped":
        return "skipped"
    return "passed"


def _first_message(case):
    """The first line of a failed testcase's failure or error, for the list printed last."""
    for child in case:
        if child.tag in ("failure", "error"):
            text = (child.get("message") or child.text or "").strip()
            return text.splitlines()[0][:160] if text else ""
    return ""


def _count_suite(suite, counts):
    """Adds the testcases of one <testsuite> (and of any nested suites) to counts; returns (testcases, failed)."""
    cases = failed = 0
    for child in suite:
        if child.tag == "testcase":
            outcome = _testcase_outcome(child)
            counts[outcome] += 1
            cases += 1
            failed += outcome == "failed"
            if outcome == "failed":
                counts["failed_cases"].append((child.get("name", "?"), _first_message(child)))
        elif child.tag == "testsuite":
            c, f = _count_suite(child, counts)
            cases += c
            failed += f
    declared = _int_attr(suite, "errors") + _int_attr(suite, "failures")
    if declared > failed:
        # Failures no testcase holds: a rostest that never ran its test node (no testcase at all), or
        # unittest subTest failures, which rosunit counts in the suite but attaches to no testcase.
        counts["failed"] += declared - failed
        counts["failed_cases"].append((suite.get("name", "?"), "declared failures no testcase holds"))
        counts["notes"].append(
            "suite '%s' reports %d error(s), %d failure(s) but %d of its %d testcase(s) failed"
            % (suite.get("name", "?"), _int_attr(suite, "errors"), _int_attr(suite, "failures"), failed, cases)
        )
        failed = declared
        cases = max(cases, 1)
    return cases, failed


def _rosunit_file(directory, test_name):
    """The results file rostest gives test node `test_name` (rosunit.xml_results_file)."""
    for c in " \"'&$!`/\\":
        test_name = test_name.replace(c, "_")
    return os.path.join(directory, "rosunit-%s.xml" % test_name)


def _drop_covered_wrappers(path, root, counts):
    """rostest-*.xml holds one wrapper testcase per <test> node ("test<name>", passed when the node ran
    and wrote rosunit-<name>.xml); the node's own testcases are in that rosunit file. A passed wrapper
    whose rosunit file is present is not counted again; a failed wrapper always counts."""
    if not os.path.basename(path).startswith("rostest-"):
        return
    for case in root.iter("testcase"):
        name = case.get("name", "")
        if not name.startswith("test") or _testcase_outcome(case) != "passed":
            continue
        rosunit = _rosunit_file(os.path.dirname(path), name[len("test"):])
        if os.path.isfile(rosunit):
            counts["passed"] -= 1
            counts["notes"].append("test node '%s' counted from %s" % (name[len("test"):], os.path.basename(rosunit)))


def count_file(path):
    """Counts for one file, or None when the file is well-formed XML but not a JUnit report."""
    counts = {"passed": 0, "failed": 0, "skipped": 0, "notes": [], "failed_cases": []}
    try:
        root = ET.parse(path).getroot()
    except (ET.ParseError, OSError) as e:
        counts["failed"] = 1
        counts["notes"].append("unreadable result file: %s" % e)
        counts["failed_cases"].append(("(file)", "unreadable result file"))
        return counts
    if root.tag == "testsuite":
        _count_suite(root, counts)
        _drop_covered_wrappers(path, root, counts)
    elif root.tag == "testsuites":
        cases = 0
        for suite in root:
            if suite.tag == "testsuite":
                cases += _count_suite(suite, counts)[0]
        if cases == 0 and (_int_attr(root, "errors") or _int_attr(root, "failures")):
            counts["failed"] += 1
            counts["failed_cases"].append(("(report)", "errors/failures but no testcase"))
            counts["notes"].append("report declares errors/failures but has no testcase")
    else:
        return None
    return counts


def find_xml_files(results_dir):
    """Distinct *.xml files under results_dir, sorted, with the number of duplicates skipped."""
    seen_paths, seen_digests, files, duplicates = set(), set(), [], 0
    for dirpath, dirnames, filenames in os.walk(results_dir):
        dirnames.sort()
        for name in sorted(filenames):
            if not name.endswith(".xml"):
                continue
            path = os.path.join(dirpath, name)
            real = os.path.realpath(path)
            if real in seen_paths:
                duplicates += 1
                continue
            seen_paths.add(real)
            try:
                with open(real, "rb") as f:
                    digest = hashlib.sha256(f.read()).hexdigest()
            except OSError:
                digest = None  # reported as unreadable by count_file
            if digest is not None and digest in seen_digests:
                duplicates += 1
                continue
            if digest is not None:
                seen_digests.add(digest)
            files.append(path)
    return files, duplicates


def main(argv):
    if len(argv) != 2 or argv[1] in ("-h", "--help"):
        print("usage: %s RESULTS_DIR" % os.path.basename(argv[0]), file=sys.stderr)
        return 2 if len(argv) != 2 else 0
    results_dir = argv[1]
    if not os.path.isdir(results_dir):
        print("%s: no such results directory: %s" % (os.path.basename(argv[0]), results_dir), file=sys.stderr)
        print("0 passed, 0 failed")
        return 1

    files, duplicates = find_xml_files(results_dir)
    passed = failed = skipped = 0
    failed_cases = []
    for path in files:
        counts = count_file(path)
        if counts is None:
            continue  # some other XML file
        rel = os.path.relpath(path, results_dir)
        line = "  %s: %d passed, %d failed" % (rel, counts["passed"], counts["failed"])
        if counts["skipped"]:
            line += ", %d skipped" % counts["skipped"]
        print(line)
        for note in counts["notes"]:
            print("    %s" % note)
        failed_cases += ["%s: %s%s" % (rel, name, " -- " + msg if msg else "") for name, msg in counts["failed_cases"]]
        passed += counts["passed"]
        failed += counts["failed"]
        skipped += counts["skipped"]
    if duplicates:
        print("(%d duplicate file(s) counted once)" % duplicates)
    if skipped:
        print("(%d skipped)" % skipped)
    if failed_cases:
        # Last but one, so that a CI log's tail names what failed.
        print("failed:")
        for case in failed_cases:
            print("  " + case)
    if passed == 0 and failed == 0:
        print("no test results found under %s" % results_dir, file=sys.stderr)
    print("%d passed, %d failed" % (passed, failed))
    return 1 if failed > 0 or passed == 0 else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
