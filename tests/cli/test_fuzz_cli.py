"""Command lines of every command, valid and invalid tokens mixed, against the CLI contract.

Hypothesis draws command lines for fk, ik, jacobian, reach, workspace (small samples), plot
(tiny drawings), check, quiz, compare, convert, selftest (few trials), robots
list/show/validate and completion: valid robots, joint values and options mixed with
huge numbers (1e300, -1e308), nan, inf, empty strings, unicode, very long strings,
negative numbers, repeated and conflicting options (--deg --rad, two orientations),
unknown options, paths that do not exist, '-' for stdin. Every run must keep the
contract of tests/cli_contract.py (exit status 0, 1 or 2, at most one line on stderr and
no traceback, strict JSON), and also:

* no NaN or infinity in any output, table or JSON;
* no numpy RuntimeWarning from any computation (the CLI filters them as a backstop;
  here the filter is off and a warning is a failure);
* nothing outside the working folder written, nothing planted there changed (bytes,
  mode, inode: a robot file, a sheet, a pose, a batch file, a drawing, a symlink, a socket
  standing for a device), except a regular file an output option names with --force.

Seeded (``derandomize=True``) and bounded: about a minute for every command together.
"""

from __future__ import annotations

import os
import re
import shutil
import socket
import stat
import warnings
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cli_contract import assert_contract, run_cli

ROOT = Path(__file__).resolve().parents[2]

# --- the working folder --------------------------------------------------------------

ROBOT_FILE = "arm.yaml"
PLANTED = {
    ROBOT_FILE: (ROOT / "robots" / "planar_3r.yaml").read_bytes(),
    # the case: a robot file whose name ends in .svg
    "robot.svg": (ROOT / "robots" / "bk_rr.yaml").read_bytes(),
    "sheet.yaml": (ROOT / "examples" / "bk_example_4_2.yaml").read_bytes(),
    "pose.txt": b"1 0 0 0.4\n0 1 0 0.1\n0 0 1 0.3\n0 0 0 1\n",
    "batch.jsonl": b'{"q": [0, 0, 0, 0, 0, 0]}\n{"xyz": [0.4, 0.1, 0.3], "rpy": [0, 90, 0]}\n',
    "batch.csv": b"x,y,z,roll,pitch,yaw\n0.4,0.1,0.3,0,90,0\n",
    "old.png": b"\x89PNG\r\n\x1a\n an existing drawing",
    "old.yaml": b"name: not a robot, a file that must survive\n",
}
LINK = "link.png"           # a symlink to old.png: --force must not replace it
FOLDER = "folder"           # a folder where a file name is expected


#: sockets: the "device" a test can make that neither blocks nor harms when opened (a FIFO
#: misread as a robot file would block the run; /dev/null replaced by a regression of
#: --force, run as root, would harm the machine)
SOCKETS = ("sock.png", "sock.yaml")


def _snapshot(work: Path) -> dict:
    out = {}
    for p in sorted(work.rglob("*")):
        st_ = os.lstat(p)
        data = p.read_bytes() if stat.S_ISREG(st_.st_mode) else None
        out[p.relative_to(work).as_posix()] = (data, st_.st_mode, st_.st_ino,
                                               os.readlink(p) if p.is_symlink() else None)
    return out


@pytest.fixture(scope="module")
def work(tmp_path_factory):
    """``base/work`` with the planted files; the tests run in ``work`` and check that
    ``base`` holds nothing else (a write that escaped the working folder)."""
    base = tmp_path_factory.mktemp("fuzz")
    work = base / "work"
    work.mkdir()
    _plant(work)
    return work


# --- tokens --------------------------------------------------------------------------

HUGE = ["1e300", "-1e308", "1e309", "-1e400", "1e10", "-1e10", "1000000001"]
ODD = ["nan", "NaN", "inf", "-inf", "Infinity", "", " ", "1e-320", "0x10", "1_000", "++1",
       "1,5", "\u0663", "\u00bd", "1e", "--", "-"]
SANE = st.one_of(st.sampled_from(["0", "1", "-1", "45", "-45", "90", "-90.5", "180", "0.3",
                                  "-0.25", "0.001", "1e9", "-1e9"]),
                 st.floats(-400, 400).map(lambda x: f"{x:.6g}"))
NUMBERS = st.one_of(
    SANE, SANE,
    st.sampled_from(HUGE + ODD),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.integers(-10**30, 10**30).map(str),
)
# text a shell can pass: no NUL (argv cannot hold one), no lone surrogates
TEXT = st.one_of(
    st.text(st.characters(blacklist_categories=("Cs",), blacklist_characters="\x00"),
            max_size=12),
    st.sampled_from(["", "x" * 5000, "\u00e9" * 300, "\u202e", "a\nb", "--", "-", "%s", "{}",
                     "$(touch pwned)", "../", "puma560\x7f"]),
)
UNKNOWN_OPTIONS = st.sampled_from(["--bogus", "-x", "--deg=1", "--json=yes", "--frame",
                                   "--xyz", "--rpy", "-o", "--output", "--help-me", "---",
                                   "-j", "-q", "--force"])
#: robots that exist, and their number of joints (a 7-joint arm is solved numerically:
#: ik and reach of an unreachable pose take seconds, so only fk, jacobian and plot get one)
DOF = {"puma560": 6, "ur5": 6, "ur5_poe": 6, "planar_3r": 3, "bk_rr": 2, "stanford_arm": 6,
       "fer_rrpr": 4, "adept_cobra600": 4, "panda": 7, "abb_irb120": 6, "bk_rrp": 3,
       ROBOT_FILE: 3, "./" + ROBOT_FILE: 3, "robot.svg": 2}
GOOD_ROBOTS = st.sampled_from(sorted(DOF))
POSE_ROBOTS = st.sampled_from(sorted(r for r, n in DOF.items() if n <= 6))
ROBOTS = st.one_of(GOOD_ROBOTS, GOOD_ROBOTS, st.sampled_from(
    ["nosuch", "puma", "no/such.yaml", "-", "", "pose.txt", FOLDER, "sheet.yaml", "x" * 5000,
     "puma560.yaml", "old.yaml", LINK, "sock.yaml", "/dev/null"]))
INPUT_PATHS = st.sampled_from(["pose.txt", "batch.jsonl", "batch.csv", "sheet.yaml",
                               ROBOT_FILE, "robot.svg", "old.yaml", "nosuch.txt", "-", "",
                               FOLDER, LINK, "/dev/null", "x" * 5000])
DRAWINGS = st.sampled_from(["new.png", "new.svg", "new.pdf", "old.png", LINK, "robot.svg",
                            "arm.png", "new.txt", "new", FOLDER, "missing/new.png",
                            "sock.png", "", "-", "new.PNG", "x" * 300 + ".png",
                            "new.png/"])
PAGES = st.sampled_from(["new.html", "new.HTM", "old.png", LINK, "robot.svg", "new.png", "new",
                         FOLDER, "missing/new.html", "sock.png", "", "-", "new.html/"])
FILES_OUT = st.sampled_from(["new.yaml", "old.yaml", ROBOT_FILE, LINK, "robot.svg",
                             "sheet.yaml", FOLDER, "missing/new.yaml", "sock.yaml", "", "-",
                             "new.yaml/"])
STDIN = st.sampled_from([b"", PLANTED["pose.txt"], PLANTED["batch.jsonl"], PLANTED["batch.csv"],
                         b'{"q": [1e300, 0, 0, 0, 0, 0]}\n', b"nan nan nan\n", b"\xff\xfe\x00",
                         PLANTED["sheet.yaml"], b"[[1,0,0,1e300],[0,1,0,0],[0,0,1,0],[0,0,0,1]]"])


def quoted(n_max=7):
    """One argument holding numbers (--from-q, --near): valid, huge, odd or garbage."""
    return st.one_of(st.lists(NUMBERS, max_size=n_max).map(" ".join), TEXT)


def choice(*valid):
    return st.one_of(st.sampled_from(list(valid)), st.sampled_from(list(valid)), TEXT)


def opt(name, value=None, n=1):
    """An option with ``n`` values drawn from ``value`` (a flag when None)."""
    if value is None:
        return st.just([name])
    return st.lists(value, min_size=n, max_size=n).map(lambda vs: [name, *vs])


def wild():
    """A token that belongs to no option: a stray number, text, an unknown option."""
    return st.one_of(NUMBERS, TEXT, UNKNOWN_OPTIONS).map(lambda t: [t])


COMMON = [opt("--deg"), opt("--rad"), opt("--unit", choice("m", "mm", "cm", "in", "ft")),
          opt("--precision", choice("0", "3", "17", "18", "-1", "1e9")), opt("--json")]
POSE = [opt("--xyz", NUMBERS, 3), opt("--rpy", NUMBERS, 3), opt("--euler-zyz", NUMBERS, 3),
        opt("--euler-xyz", NUMBERS, 3), opt("--quat", NUMBERS, 4),
        opt("--axis-angle", NUMBERS, 4), opt("--matrix", NUMBERS, 9),
        opt("--approach", NUMBERS, 3), opt("--tcv", NUMBERS, 6), opt("--pose", INPUT_PATHS),
        opt("--from-q", quoted())]
BATCH = [opt("--batch", INPUT_PATHS), opt("--format", choice("jsonl", "csv"))]
SEEDS = choice("0", "1", "7", "-1", "99999999999999999999", "1e3")
SMALL_DPI = choice("10", "12", "5", "1201", "-10")


#: mostly sane, sometimes huge or odd: a joint value or coordinate in the right place
VALUE = st.one_of(SANE, SANE, SANE, NUMBERS)


@st.composite
def robot_and_joints(draw):
    """A robot that exists and the right number of joint values (or none: home)."""
    robot = draw(GOOD_ROBOTS)
    q = draw(st.one_of(st.lists(VALUE, min_size=DOF[robot], max_size=DOF[robot]), st.just([])))
    return [robot, *q]


@st.composite
def robot_and_pose(draw):
    """A robot that exists and a pose it may or may not reach."""
    robot = draw(POSE_ROBOTS)
    n = DOF[robot]
    q = " ".join(draw(st.lists(VALUE, min_size=n, max_size=n)))
    xyz = draw(st.lists(st.one_of(st.sampled_from(["0", "0.3", "0.5", "-0.2", "1", "12.99",
                                                   "2.5", "400"]), VALUE),
                        min_size=3, max_size=3))
    rpy = draw(st.lists(VALUE, min_size=3, max_size=3))
    return draw(st.sampled_from([[robot, "--from-q", q], [robot, "--xyz", *xyz, "--rpy", *rpy],
                                 [robot, "--xyz", *xyz], [robot, "--pose", "pose.txt"]]))


def just(*argv):
    return st.just(list(argv))


#: command path -> (valid command lines, their options, examples)
COMMANDS = {
    ("fk",): (robot_and_joints(), [opt("--frames"), *BATCH, *COMMON], 250),
    ("jacobian",): (robot_and_joints(),
                    [opt("--frame", choice("base", "tool")),
                     opt("--analytic", choice("rpy", "zyz", "xyz")), *BATCH, *COMMON], 200),
    ("ik",): (robot_and_pose(),
              [*POSE, opt("--all-branches"), opt("--explain"), opt("--near", quoted()),
               opt("--numeric"), opt("--plot", DRAWINGS), opt("--dpi", SMALL_DPI),
               opt("--force"), *BATCH, *COMMON], 350),
    ("reach",): (robot_and_pose(), [*POSE, *BATCH, *COMMON], 200),
    ("workspace",): (st.tuples(st.sampled_from(["bk_rr", "planar_3r", ROBOT_FILE, "robot.svg",
                                                "bk_rrp"])).map(list),
                     [opt("--samples", choice("1000", "1200", "999", "0", "-5", "1e9")),
                      opt("--seed", SEEDS),
                      opt("--dexterity", choice("1", "0.5", "0", "nan", "inf", "-1", "2",
                                                "1e300")),
                      opt("--orientations", choice("2", "4", "1", "-3")),
                      opt("--plot", DRAWINGS), opt("--dpi", SMALL_DPI), opt("--force"),
                      *COMMON], 15),
    ("plot",): (robot_and_joints().map(lambda a: a + ["-o", "new.png"]),
                [opt("-o", DRAWINGS), opt("--output", DRAWINGS), opt("--dpi", SMALL_DPI),
                 opt("--force"), opt("--deg"), opt("--rad"),
                 opt("--unit", choice("m", "mm", "ft"))], 50),
    ("view",): (robot_and_joints().map(lambda a: a + ["-o", "new.html"]),
                [opt("-o", PAGES), opt("--output", PAGES), opt("--force"), opt("--deg"),
                 opt("--rad"), opt("--unit", choice("m", "mm", "ft")),
                 opt("--xyz", NUMBERS, 3), opt("--rpy", NUMBERS, 3),
                 opt("--from-q", quoted()), opt("--pose", INPUT_PATHS)], 40),
    ("check",): (st.lists(st.sampled_from(["sheet.yaml", "sheet.yaml", "-"]), min_size=1,
                          max_size=2),
                 [opt("-q"), opt("--quiet"), opt("--precision", choice("2", "-1")),
                  opt("--json")], 60),
    ("quiz",): (st.tuples(GOOD_ROBOTS, st.sampled_from(["1", "2"])).map(
                    lambda t: [t[0], "--seed", t[1], "--items", "fk,jacobian"]),
                [opt("--seed", SEEDS), opt("--answers"),
                 opt("--items", choice("fk", "dh,link", "jacobian,singular", "ik", "reach",
                                       "fk,fk", ",", "bogus")),
                 opt("-o", FILES_OUT), opt("--force"), opt("--deg"), opt("--rad")], 50),
    ("compare",): (st.lists(GOOD_ROBOTS, min_size=2, max_size=2),
                   [opt("--allow-offsets"), opt("--free-base"), opt("--free-tool"),
                    opt("--samples", choice("1", "20", "0", "2000000")),
                    opt("--seed", SEEDS), *COMMON], 60),
    ("convert",): (st.tuples(GOOD_ROBOTS, st.sampled_from(["dh", "mdh", "poe"])).map(
                       lambda t: [t[0], "--to", t[1]]),
                   [opt("--to", choice("dh", "mdh", "poe")), opt("-o", FILES_OUT),
                    opt("--output", FILES_OUT), opt("--force")], 100),
    ("selftest",): (st.tuples(GOOD_ROBOTS).map(list),
                    [opt("--trials", choice("1", "5", "20", "0", "-1")),
                     opt("--seed", SEEDS), opt("--json")], 40),
    ("robots", "list"): (just(), [opt("--json")], 5),
    ("robots", "show"): (st.tuples(GOOD_ROBOTS).map(list), COMMON, 60),
    ("robots", "validate"): (st.lists(st.one_of(GOOD_ROBOTS, INPUT_PATHS), min_size=1,
                                      max_size=3), [opt("--json")], 80),
    ("completion",): (st.tuples(st.sampled_from(["bash", "zsh", "fish"])).map(list),
                      [wild()], 10),
}
#: what a wild part of a command line may put in place of a valid one
WILD_HEAD = st.one_of(ROBOTS.map(lambda r: [r]), st.lists(NUMBERS, max_size=7),
                      st.lists(INPUT_PATHS, max_size=2), st.just([]))


def command_lines(path):
    """``(argv, stdin)``: mostly a valid command line with a few of the command's options
    (valid values or not) after its first argument; else a valid one with up to six
    pieces (options, wild tokens) anywhere, or a wild one from the start."""
    valid, options, _ = COMMANDS[path]
    pieces = st.one_of(*options, wild()) if options else wild()

    @st.composite
    def build(draw):
        mode = draw(st.sampled_from(["plain", "plain", "options", "options", "options",
                                     "mixed", "mixed", "wild"]))
        head = draw(WILD_HEAD if mode == "wild" else valid)
        count = {"plain": 0, "options": draw(st.integers(1, 3))}.get(
            mode, draw(st.integers(0, 6)))
        chunks = [[t] for t in head]
        first = 0 if mode in ("mixed", "wild") else min(1, len(chunks))
        for piece in draw(st.lists(st.one_of(*options) if options and mode == "options"
                                   else pieces, min_size=count, max_size=count)):
            chunks.insert(draw(st.integers(first, len(chunks))), piece)   # kept whole
        argv = list(path) + [t for c in chunks for t in c]
        if path[0] in ("ik", "reach") or (path[0] == "view" and any(
                a in ("--xyz", "--rpy", "--from-q", "--pose") for a in argv)):
            argv = [a if a not in DOF or DOF[a] <= 6 else "puma560" for a in argv]
        if path[0] == "workspace":       # sampling a 6-joint arm takes seconds: small arms
            argv = [a if a not in DOF or DOF[a] <= 3 else "bk_rr" for a in argv]
            if "--samples" not in argv:
                argv += ["--samples", "1000"]        # the default (200000) is for people
        if path[0] == "plot" and "--dpi" not in argv:
            argv += ["--dpi", "10"]
        if path[0] == "selftest" and "--trials" not in argv:
            argv += ["--trials", "3"]
        if path[0] == "compare" and "--samples" not in argv:
            argv += ["--samples", "10"]
        return argv, draw(STDIN)
    return build()


# --- invariants beyond the contract ----------------------------------------------------

NONFINITE = re.compile(r"(?<![\w.])-?(nan|inf|infinity)(?![\w])", re.I)
#: informational lines some commands add on stderr besides the one error line
NOTES = re.compile(r"^kincalc: (note: |seed \d+ |wrote |no solution to draw|the tool moves "
                   r"along a line)")


def _shown(argv) -> str:
    return "kincalc " + " ".join(a if len(a) < 40 else a[:20] + f"...({len(a)})" for a in argv)


def _check_output_is_finite(out: str, argv) -> None:
    """No 'nan' or 'inf' in a table (JSON is parsed strictly by the contract). A word the
    user typed may come back as text (a file named 'inf'): then tables are not checked."""
    if any(NONFINITE.search(a) for a in argv) or "--json" in argv or argv[0] == "view":
        return                            # (view prints a web page, not a table)
    for line in out.splitlines():
        m = NONFINITE.search(line)
        assert m is None, f"{_shown(argv)}: non-finite number in output: " \
                          f"{line[:300]!r}"


def _contract(status, out, err, argv):
    lines = err.splitlines()
    errors = [x for x in lines if not NOTES.match(x)]
    if argv[0] == "check" or argv[:2] == ["robots", "validate"]:   # a line per bad file
        errors = errors[:1] if all(x.startswith("kincalc: error: ") for x in errors) else errors
    assert_contract(status, out, "".join(x + "\n" for x in errors), argv)


def _plant(work: Path) -> dict:
    """Put the working folder in its planted state (whatever a failed run left) and
    return its snapshot, so that every run starts alike and a failure is its own."""
    for p in list(work.iterdir()):
        name = p.name
        if name == LINK and p.is_symlink() and os.readlink(p) == "old.png":
            continue
        if name == FOLDER and p.is_dir() and not p.is_symlink() and not any(p.iterdir()):
            continue
        if name in SOCKETS and stat.S_ISSOCK(os.lstat(p).st_mode):
            continue
        if name in PLANTED and p.is_file() and not p.is_symlink() \
                and p.read_bytes() == PLANTED[name] and stat.S_IMODE(p.stat().st_mode) == 0o644:
            continue
        if p.is_dir() and not p.is_symlink():
            shutil.rmtree(p)
        else:
            p.unlink()
    for name, data in PLANTED.items():
        if not (work / name).exists():
            (work / name).write_bytes(data)
            os.chmod(work / name, 0o644)
    if not (work / LINK).is_symlink():
        os.symlink("old.png", work / LINK)
    (work / FOLDER).mkdir(exist_ok=True)
    for name in SOCKETS:
        if not os.path.lexists(work / name):
            with socket.socket(socket.AF_UNIX) as sock:
                old = os.getcwd()
                os.chdir(work)                    # a short address: sun_path is 108 bytes
                try:
                    sock.bind(name)
                finally:
                    os.chdir(old)
    return _snapshot(work)


def _run_checked(argv, stdin, work: Path):
    before = _plant(work)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", RuntimeWarning)
        status, out, err = run_cli(argv, stdin, cwd=str(work))
    numeric = [w for w in caught if issubclass(w.category, RuntimeWarning)]
    assert not numeric, (f"{_shown(argv)}: numpy warning: "
                         f"{numeric[0].message} ({numeric[0].filename}:{numeric[0].lineno})")
    _contract(status, out, err, argv)
    _check_output_is_finite(out, argv)
    after = _snapshot(work)
    replaceable = _replaceable(argv)
    for name, snap in before.items():
        assert after.get(name) == snap or name in replaceable, f"{_shown(argv)}: {name} changed"
    assert sorted(os.listdir(work.parent)) == ["work"], \
        f"{_shown(argv)}: wrote outside its working folder"
    return status


OUTPUT_OPTIONS = ("-o", "--output", "--plot")


def _replaceable(argv) -> set:
    """The planted regular files this command line may replace: named by an output
    option, with --force, and named nowhere else (a file that is also the robot or a
    --pose file is an input, never to be written)."""
    if "--force" not in argv:
        return set()
    names = [os.path.normpath(a) for a in argv]
    out = [names[k + 1] for k, a in enumerate(argv[:-1]) if a in OUTPUT_OPTIONS]
    return {n for n in out if n in PLANTED and names.count(n) == out.count(n)}


@pytest.fixture()
def no_backstop(monkeypatch):
    """Let numpy's warnings through, to see whether any computation raises one."""
    import kincalc.cli.main as m
    monkeypatch.setattr(m, "_quiet_numeric_warnings", lambda debug: None)


def _tree(folder: Path) -> dict:
    """What a stray write into the source tree or the robot library would change (the
    tools' own dot-folders aside: hypothesis writes its caches into .hypothesis when it
    first runs, which may be during this test on a fresh clone)."""
    return {p.name: os.lstat(p).st_mtime_ns for p in [*folder.iterdir(),
                                                      *(folder / "robots").iterdir()]
            if not p.name.startswith(".")}


@pytest.mark.parametrize("path", list(COMMANDS), ids=" ".join)
def test_command_lines_keep_the_contract(path, work, no_backstop):
    tree = _tree(ROOT)

    @settings(derandomize=True, database=None, deadline=None, max_examples=COMMANDS[path][2],
              suppress_health_check=list(HealthCheck))
    @given(command_lines(path))
    def run(case):
        argv, stdin = case
        _run_checked(argv, stdin, work)

    run()
    assert _tree(ROOT) == tree, "a command line wrote into the source tree"
