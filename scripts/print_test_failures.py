"""Prints the failed test cases of JUnit XML reports with their messages.

Usage: python3 scripts/print_test_failures.py DIR [--lines N] (a CI tool: scripts/run_tests.sh runs
it, it is not installed).

catkin_test_results prints only counts per report; a CI log that ends in a failure then says
which report failed but not which case or why. This walks DIR for *.xml reports (gtest, rosunit,
rostest) and prints, for each failed or errored test case, its report, suite and name and the
first N lines (default 12) of each failure's message and text.
"""
import argparse
import os
import sys
import xml.etree.ElementTree as ElementTree


def failed_cases(path):
    """The (suite, name, [texts]) of the failed or errored test cases of one report."""
    try:
        root = ElementTree.parse(path).getroot()
    except ElementTree.ParseError as error:
        return [("", os.path.basename(path), ["unreadable report: %s" % error])]
    out = []
    for case in root.iter("testcase"):
        texts = []
        for problem in list(case.findall("failure")) + list(case.findall("error")):
            message = problem.get("message") or ""
            body = problem.text or ""
            texts.append(message if message.strip() and message.strip() in body else (message + "\n" + body))
        if texts:
            out.append((case.get("classname", ""), case.get("name", ""), texts))
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("directory")
    parser.add_argument("--lines", type=int, default=12, help="lines of each message to print")
    args = parser.parse_args()
    seen = set()
    for folder, _, files in sorted(os.walk(args.directory)):
        for name in sorted(files):
            if not name.endswith(".xml"):
                continue
            path = os.path.join(folder, name)
            for suite, case, texts in failed_cases(path):
                # rostest writes a case into two reports (rosunit-*.xml and rostest-*.xml): once.
                key = (suite, case, tuple(texts))
                if key in seen:
                    continue
                seen.add(key)
                print("FAILED %s: %s.%s" % (os.path.relpath(path, args.directory), suite, case))
                for text in texts:
                    lines = [line for line in text.strip().splitlines() if line.strip()]
                    for line in lines[: args.lines]:
                        print("    " + line)
                    if len(lines) > args.lines:
                        print("    ... (%d more lines in %s)" % (len(lines) - args.lines, path))
    return 0


if __name__ == "__main__":
    sys.exit(main())
