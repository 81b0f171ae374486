#!/usr/bin/env python3
"""Runs one module of test/python as plain unittest and writes its JUnit results, which make test-unit and make
test count (test/tools/count_test_results.py): junit_unittest.py MODULE.py RESULTS.xml. Prints unittest's own
report too; exits 1 when a test failed. `python3 -m unittest` runs the same tests without the results file."""
import importlib.util
import os
import sys
import time
import traceback
import unittest
import xml.etree.ElementTree as ET


class JUnitResult(unittest.TextTestResult):
    """unittest's text result that also keeps each test's outcome, time and message."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self.cases = []  # (test id, seconds, outcome or None, message)

    def startTest(self, test):
        self._started = time.time()
        self._outcome = None
        super().startTest(test)

    def _set(self, kind, message):
        self._outcome = (kind, message)

    def addError(self, test, err):
        super().addError(test, err)
        self._set('error', self._exc_info_to_string(err, test))

    def addFailure(self, test, err):
        super().addFailure(test, err)
        self._set('failure', self._exc_info_to_string(err, test))

    def addSubTest(self, test, subtest, err):
        super().addSubTest(test, subtest, err)
        if err is not None:
            self._set('failure', '%s: %s' % (subtest.id(), self._exc_info_to_string(err, test)))

    def addSkip(self, test, reason):
        super().addSkip(test, reason)
        self._set('skipped', reason)

    def addUnexpectedSuccess(self, test):
        super().addUnexpectedSuccess(test)
        self._set('failure', 'unexpected success')

    def stopTest(self, test):
        super().stopTest(test)
        self.cases.append((test.id(), time.time() - self._started, self._outcome))


def write_junit(path, name, result, seconds):
    suite = ET.Element('testsuite', name=name, tests=str(len(result.cases)), time='%.3f' % seconds,
                       failures=str(sum(1 for *_, o in result.cases if o and o[0] == 'failure')),
                       errors=str(sum(1 for *_, o in result.cases if o and o[0] == 'error')),
                       skipped=str(sum(1 for *_, o in result.cases if o and o[0] == 'skipped')))
    for test_id, took, outcome in result.cases:
        classname, _, method = test_id.rpartition('.')
        case = ET.SubElement(suite, 'testcase', classname=classname, name=method, time='%.3f' % took)
        if outcome:
            kind, message = outcome
            child = ET.SubElement(case, kind, message=message.strip().splitlines()[-1][:500] if message else '')
            child.text = message
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    ET.ElementTree(suite).write(path, encoding='utf-8', xml_declaration=True)


def main(argv):
    if len(argv) != 3:
        print('usage: junit_unittest.py MODULE.py RESULTS.xml', file=sys.stderr)
        return 2
    module_path, results = argv[1], argv[2]
    name = os.path.splitext(os.path.basename(module_path))[0]
    sys.path.insert(0, os.path.dirname(os.path.abspath(module_path)))
    started = time.time()
    spec = importlib.util.spec_from_file_location(name, module_path)
    module = importlib.util.module_from_spec(spec)
    try:
        spec.loader.exec_module(module)
        suite = unittest.defaultTestLoader.loadTestsFromModule(module)
    except Exception:  # a module that does not import is one failed test, with the reason
        failure = traceback.format_exc()

        def imports():
            raise AssertionError('%s does not import:\n%s' % (module_path, failure))
        suite = unittest.TestSuite([unittest.FunctionTestCase(imports, description=name)])
    runner = unittest.TextTestRunner(verbosity=2, resultclass=JUnitResult)
    result = runner.run(suite)
    write_junit(results, name, result, time.time() - started)
    return 0 if result.wasSuccessful() else 1


if __name__ == '__main__':
    sys.exit(main(sys.argv))
