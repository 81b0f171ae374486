"""Tests that need root (a network namespace with an sshd of its own, a SLURM of its own, a tmpfs to fill):
skipped with the reason when not root, and recorded as skipped, not passed, in their JUnit results (rosunit's
runner would record a skip as a pass). CI runs as root, where they run."""
import os
import subprocess
import sys
import unittest
import xml.etree.ElementTree as ET


def _sudo_without_password():
    try:
        return subprocess.run(['sudo', '-n', 'true'], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                              timeout=30).returncode == 0
    except (OSError, subprocess.TimeoutExpired):
        return False


def needs_root(what, sudo=False):
    """Skips a test (or a TestCase) unless root; `what` says what needs it. `sudo`: the test can also use
    `sudo -n`, which is then enough."""
    allowed = os.geteuid() == 0 or (sudo and _sudo_without_password())
    return unittest.skipUnless(allowed, '%s needs root%s; run the test as root (CI does)'
                               % (what, ' or sudo without a password' if sudo else ''))


def _record_skips():
    """Makes rosunit's XML runner write <skipped message=...> for a skipped test, and say so on stderr."""
    from rosunit import xmlrunner
    result, info = xmlrunner._XMLTestResult, xmlrunner._TestInfo
    if getattr(result, 'records_skips', False):
        return
    start, stop, xml, text = result.startTest, result.stopTest, info.xml, info.print_report_text

    def start_test(self, test):
        self.skip_reason = None
        start(self, test)

    def add_skip(self, test, reason):
        unittest.TestResult.addSkip(self, test, reason)
        self.skip_reason = reason
        print('SKIPPED %s: %s' % (test.id(), reason), file=sys.stderr)

    def stop_test(self, test):
        stop(self, test)
        self._tests[-1].skip_reason = getattr(self, 'skip_reason', None)

    def info_xml(self):
        case = xml(self)
        if getattr(self, 'skip_reason', None) is not None:
            ET.SubElement(case, 'skipped', message=self.skip_reason)
        return case

    def info_text(self, stream):
        if getattr(self, 'skip_reason', None) is None:
            return text(self, stream)
        stream.write('[Testcase: %s] ... skipped: %s\n' % (self._method, self.skip_reason))

    result.startTest, result.addSkip, result.stopTest = start_test, add_skip, stop_test
    info.xml, info.print_report_text = info_xml, info_text
    result.records_skips = True


def rosrun(package, name, case):
    """rostest.rosrun(package, name, case), its skipped tests recorded as skipped."""
    import rostest
    _record_skips()
    rostest.rosrun(package, name, case)
