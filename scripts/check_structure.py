#!/usr/bin/python3
"""The house's structure rules, checked from the source tree alone (no build), one test per rule.

- layering: the C++ of include/se3_interpolation/ and src/ is layered by folder, each folder
  including only its own and lower ones (LAYERS below), and no file includes itself through others;
- file size: no production file (include/, src/) over MAX_FILE_LINES lines;
- function size: no function body in include/ or src/ over MAX_FUNCTION_LINES lines, from the line
  of its opening brace to the line of its closing brace;
- named paths: every path of this repository that a comment (C++, Python, shell, CMake) or a page
  (README.md, docs/, CHANGELOG.rst) names exists;
- the header table: every public header has its row in docs/api.md;
- the format: the C++ of include/ and src/ is as clang-format writes it with .clang-format.

Prints each finding as FILE:LINE: message, then `structure: N passed, N failed`; exits 1 on a
finding. Usage: check_structure.py [ROOT] (default: the repository holding this script).
"""
import os
import re
import subprocess
import sys

MAX_FILE_LINES = 500
MAX_FUNCTION_LINES = 80

# Lowest first: a folder includes only itself and the folders before it. `base` is
# include/se3_interpolation/*.h (exceptions, deadline, name tables), which every layer may use;
# `arm` (the kinematic chain of a robot arm) needs the mathematics and geometry only. The execution
# (goals, playback, stops) is below the planner: the planner samples its motions for it
# (sample_tolerance refines the samples until the goal they make follows the motion).
LAYERS = ["base", "math", "geometry", "curves", "analysis", "timing", "fitting", "arm", "execution",
          "planner", "python", "ros", "cli"]

# Files that the build generates, named in comments: dynamic_reconfigure's header of cfg/*.cfg
# and the node parameter table that cfg/node_parameter_table.py writes.
GENERATED = {"InterpolationNodeConfig.h", "node_parameter_table.h"}

# Top-level folders of the repository: a path in a comment that starts with one of them (or with
# a folder of include/se3_interpolation/) names a file of this repository.
PATH_TOKEN = re.compile(r"(?<![\w/.\-$])((?:[\w.\-]+/)*[\w\-]+\.(?:h|hpp|cpp|py|sh|md|rst|yaml|launch|test|srv|msg|"
                        r"action|cfg|txt|rviz|xml|png|csv|urdf))(?![\w/])")


def source_files(root, folders, suffixes):
    for folder in folders:
        for dirpath, _, names in os.walk(os.path.join(root, folder)):
            for name in sorted(names):
                if name.endswith(suffixes):
                    yield os.path.relpath(os.path.join(dirpath, name), root)


def layer_of(path):
    parts = path.split("/")
    if parts[0] == "include":
        return parts[2] if len(parts) > 3 else "base"
    return parts[1] if len(parts) > 2 else "base"


def includes_of(root, path):
    """The repository files that `path` includes with quotes, as (line, included path)."""
    found = []
    with open(os.path.join(root, path), errors="replace") as f:
        for number, line in enumerate(f, 1):
            m = re.match(r'\s*#\s*include\s+"([^"]+)"', line)
            if not m:
                continue
            name = m.group(1)
            for candidate in (os.path.join("include", name), os.path.join(os.path.dirname(path), name)):
                candidate = os.path.normpath(candidate)
                if os.path.isfile(os.path.join(root, candidate)):
                    found.append((number, candidate))
                    break
    return found


def check_layering(root, files):
    findings = []
    graph = {}
    for path in files:
        graph[path] = [target for _, target in includes_of(root, path)]
        mine = layer_of(path)
        for number, target in includes_of(root, path):
            theirs = layer_of(target)
            if mine not in LAYERS or theirs not in LAYERS:
                findings.append("%s:%d: folder '%s' or '%s' has no place in the layering (scripts/check_structure.py, "
                                "LAYERS)" % (path, number, mine, theirs))
            elif LAYERS.index(theirs) > LAYERS.index(mine):
                findings.append("%s:%d: %s includes %s, a higher layer (%s > %s)" % (path, number, path, target,
                                                                                   theirs, mine))
    # Include cycles: a depth-first search that reports each back edge once.
    state = {}

    def visit(node, stack):
        state[node] = 1
        stack.append(node)
        for target in graph.get(node, []):
            if state.get(target) == 1:
                cycle = stack[stack.index(target):] + [target]
                findings.append("%s: include cycle %s" % (node, " -> ".join(cycle)))
            elif target in graph and state.get(target) is None:
                visit(target, stack)
        stack.pop()
        state[node] = 2

    for node in sorted(graph):
        if state.get(node) is None:
            visit(node, [])
    return findings


def code_lines(path):
    """The file's lines with comments, string and character literals blanked (lines kept)."""
    with open(path, errors="replace") as f:
        text = f.read()
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("\n" * text.count("\n", i, j))
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(c + c)
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out).split("\n")


SIGNATURE_END = re.compile(r"\)\s*(?:const\b\s*)?(?:noexcept\b\s*)?(?:override\b\s*)?(?:final\b\s*)?"
                           r"(?:->\s*[\w:<>,\s*&]+)?$")
CONTROL = re.compile(r"(?:^|[^\w])(?:if|for|while|switch|catch)\s*\(")
LAMBDA = re.compile(r"\]\s*\([^()]*\)\s*(?:mutable\b\s*)?(?:->\s*[\w:<>,\s*&]+)?$")


def long_functions(root, path):
    """(first line, length) of each function body longer than MAX_FUNCTION_LINES."""
    lines = code_lines(os.path.join(root, path))
    found = []
    stack = []  # (is_function, line index)
    statement = ""  # the code since the last ';', '{' or '}'
    for index, line in enumerate(lines):
        for c in line:
            if c == "{":
                head = statement.strip()
                inside = any(kind for kind, _ in stack)
                is_function = (not inside and SIGNATURE_END.search(head) is not None and
                               CONTROL.search(head) is None and LAMBDA.search(head) is None)
                stack.append((is_function, index))
                statement = ""
            elif c == "}":
                if stack:
                    is_function, start = stack.pop()
                    if is_function and index - start + 1 > MAX_FUNCTION_LINES:
                        found.append((start + 1, index - start + 1))
                statement = ""
            elif c == ";":
                statement = ""
            else:
                statement += c
        statement += " "
    return found


def check_sizes(root, files):
    file_findings, function_findings = [], []
    for path in files:
        with open(os.path.join(root, path), errors="replace") as f:
            count = sum(1 for _ in f)
        if count > MAX_FILE_LINES:
            file_findings.append("%s: %d lines (at most %d)" % (path, count, MAX_FILE_LINES))
        if path.endswith((".h", ".cpp")):
            for start, length in long_functions(root, path):
                function_findings.append("%s:%d: a function of %d lines (at most %d)" %
                                         (path, start, length, MAX_FUNCTION_LINES))
    return file_findings, function_findings


def check_named_paths(root):
    findings = []
    top = {name for name in os.listdir(root) if os.path.isdir(os.path.join(root, name)) and not name.startswith(".")}
    include_root = os.path.join(root, "include", "se3_interpolation")
    sub = {name for name in os.listdir(include_root) if os.path.isdir(os.path.join(include_root, name))}
    projects = top | sub | {"se3_interpolation", ".ci"}
    basenames = set()
    for dirpath, dirnames, names in os.walk(root):
        dirnames[:] = [d for d in dirnames if not d.startswith(".") or d == ".ci"]
        basenames.update(names)

    def exists(token, here):
        bases = ["", "include", "include/se3_interpolation", "src", os.path.dirname(here)]
        return any(os.path.exists(os.path.normpath(os.path.join(root, base, token))) for base in bases)

    def scan(path, numbered):
        for number, text in numbered:
            text = re.sub(r"https?://\S+", "", text)
            for m in PATH_TOKEN.finditer(text):
                token = m.group(1).split("#")[0]
                first = token.split("/")[0]
                if token in GENERATED or os.path.basename(token) in GENERATED:
                    continue
                if "/" in token and (first in projects or first == ".."):
                    ok = exists(token, path)
                elif "/" not in token and token.endswith((".h", ".cpp")):
                    ok = token in basenames
                else:
                    continue
                if not ok:
                    findings.append("%s:%d: names %s, which does not exist" % (path, number, token))

    for path in source_files(root, ["include", "src", "test", "bench", "scripts"], (".h", ".cpp")):
        with open(os.path.join(root, path), errors="replace") as f:
            scan(path, [(n, line.split("//", 1)[1]) for n, line in enumerate(f, 1)
                        if "//" in line and not line.lstrip().startswith("#include")])
    hash_comments = list(source_files(root, ["scripts", "src", "test", "bench", "launch", "config", "cfg", ".ci"],
                                      (".py", ".sh", ".launch", ".test", ".yaml", "run")))
    hash_comments.append("CMakeLists.txt")
    hash_comments += [p for p in source_files(root, ["test"], ("CMakeLists.txt",))]
    for path in hash_comments:
        with open(os.path.join(root, path), errors="replace") as f:
            scan(path, [(n, line.split("#", 1)[1]) for n, line in enumerate(f, 1) if "#" in line])
    pages = ["README.md", "CHANGELOG.rst"] + list(source_files(root, ["docs"], (".md",)))
    for path in pages:
        with open(os.path.join(root, path), errors="replace") as f:
            scan(path, list(enumerate(f, 1)))
    return findings


def check_format(root, files):
    """The C++ of include/ and src/ as clang-format writes it with the committed .clang-format."""
    try:
        result = subprocess.run(["clang-format", "--dry-run", "--style=file"] + files, cwd=root,
                                capture_output=True, text=True)
    except OSError:
        return ["clang-format is not installed (Debian package clang-format)"]
    drifted = sorted({line.split(":")[0] for line in result.stderr.splitlines() if ": warning: code should be" in line})
    findings = ["%s: not as clang-format writes it (clang-format -i --style=file %s)" % (path, path)
                for path in drifted]
    if result.returncode != 0 and not findings:
        findings.append("clang-format failed: " + result.stderr.strip()[:500])
    return findings


def check_api_table(root):
    """Every public header of include/se3_interpolation/ has its row in docs/api.md (as `folder/name.h`,
    or its folder's `folder/*.h`)."""
    with open(os.path.join(root, "docs", "api.md"), errors="replace") as f:
        page = f.read()
    findings = []
    for path in source_files(root, ["include/se3_interpolation"], (".h",)):
        name = os.path.relpath(path, "include/se3_interpolation")
        pattern = os.path.join(os.path.dirname(name), "*.h")
        if "`%s`" % name not in page and "`%s`" % pattern not in page:
            findings.append("%s: not in docs/api.md's table of headers" % path)
    return findings


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
    production = list(source_files(root, ["include/se3_interpolation", "src"], (".h", ".cpp", ".py")))
    cpp = [p for p in production if p.endswith((".h", ".cpp"))]
    file_findings, function_findings = check_sizes(root, production)
    rules = [
        ("layering and include cycles", check_layering(root, cpp)),
        ("files of at most %d lines" % MAX_FILE_LINES, file_findings),
        ("functions of at most %d lines" % MAX_FUNCTION_LINES, function_findings),
        ("paths named in comments and pages exist", check_named_paths(root)),
        ("every public header in docs/api.md", check_api_table(root)),
        ("clang-format of include/ and src/", check_format(root, cpp)),
    ]
    passed = failed = 0
    for name, findings in rules:
        if findings:
            failed += 1
            print("FAIL %s: %d finding(s)" % (name, len(findings)))
            for finding in findings:
                print("  " + finding)
        else:
            passed += 1
            print("PASS %s" % name)
    print("structure: %d passed, %d failed" % (passed, failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
