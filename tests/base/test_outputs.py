"""Outputs never destroy anything (issue 14, item 7).

The rules live in :mod:`kincalc.outputs` and are tested there (refusals, --force on
regular files only, inputs never written, temporary file and rename, modes); every
writer (plot -o, ik --plot, workspace --plot, convert -o, quiz -o) is then tested to go
through them, with the cases of the issue: a robot file named robot.svg drawn over
itself, /dev/null replaced by --force, convert's 0600 files.
"""

from __future__ import annotations

import os
import stat
from pathlib import Path

import pytest

from cli_contract import assert_contract, run_cli
from kincalc import outputs
from kincalc.errors import InputError
from kincalc.outputs import Target, check_target, replacing, write_text

ROOT = Path(__file__).resolve().parents[2]


def mode(path) -> int:
    return stat.S_IMODE(os.lstat(path).st_mode)


@pytest.fixture()
def umask022():
    old = os.umask(0o022)
    yield
    os.umask(old)


# --- the module ------------------------------------------------------------------------

def test_new_file_is_written_whole_with_the_umask_mode(tmp_path, umask022):
    write_text(Target(str(tmp_path / "a.txt")), "hello\n")
    assert (tmp_path / "a.txt").read_text() == "hello\n"
    assert mode(tmp_path / "a.txt") == 0o644
    os.umask(0o077)
    write_text(Target(str(tmp_path / "b.txt")), "x")
    assert mode(tmp_path / "b.txt") == 0o600
    os.umask(0o002)
    write_text(Target(str(tmp_path / "c.txt")), "x")
    assert mode(tmp_path / "c.txt") == 0o664
    assert sorted(os.listdir(tmp_path)) == ["a.txt", "b.txt", "c.txt"]   # no temporary left


def test_umask_is_read_without_changing_it():
    old = os.umask(0o027)
    try:
        assert outputs._umask() == 0o027
        assert os.umask(0o027) == 0o027
    finally:
        os.umask(old)


def test_existing_file_needs_force_and_keeps_its_mode(tmp_path):
    f = tmp_path / "a.txt"
    f.write_text("old")
    os.chmod(f, 0o640)
    with pytest.raises(InputError, match=r"^-o .*a\.txt: the file exists; use --force"):
        write_text(Target(str(f)), "new")
    assert f.read_text() == "old"
    write_text(Target(str(f), force=True), "new")
    assert f.read_text() == "new" and mode(f) == 0o640


@pytest.mark.parametrize("force", [False, True])
def test_symlink_is_refused_and_its_target_untouched(tmp_path, force):
    real = tmp_path / "real.txt"
    real.write_text("keep")
    link = tmp_path / "link.txt"
    link.symlink_to(real)
    with pytest.raises(InputError, match="is a symbolic link; kincalc replaces regular files "
                                         "only, even with --force"):
        write_text(Target(str(link), force=force), "new")
    assert link.is_symlink() and real.read_text() == "keep"
    dangling = tmp_path / "dangling.txt"
    dangling.symlink_to(tmp_path / "nowhere")
    with pytest.raises(InputError, match="symbolic link"):
        write_text(Target(str(dangling), force=force), "new")
    assert not (tmp_path / "nowhere").exists()


@pytest.mark.parametrize("force", [False, True])
def test_devices_fifos_and_folders_are_refused(tmp_path, force):
    with pytest.raises(InputError, match="is a character device"):
        check_target(Target("/dev/null", force=force))
    assert stat.S_ISCHR(os.stat("/dev/null").st_mode)
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    with pytest.raises(InputError, match=r"is a named pipe \(FIFO\)"):
        write_text(Target(str(fifo), force=force), "x")
    assert stat.S_ISFIFO(os.lstat(fifo).st_mode)
    with pytest.raises(InputError, match="is a folder"):
        write_text(Target(str(tmp_path), force=force), "x")
    with pytest.raises(InputError, match="names a folder"):
        write_text(Target(str(tmp_path / "new") + "/", force=force), "x")


def test_inputs_are_never_written_however_named(tmp_path):
    src = tmp_path / "robot.yaml"
    src.write_text("robot")
    (tmp_path / "hard.yaml").hardlink_to(src)
    (tmp_path / "soft.yaml").symlink_to(src)
    inputs = (("the robot file", str(src)),)
    for name in ("robot.yaml", "./robot.yaml", "hard.yaml", "soft.yaml",
                 f"../{tmp_path.name}/robot.yaml"):
        for force in (False, True):
            with pytest.raises(InputError, match="that is the robot file, which this command "
                                                 "reads; kincalc never writes over its input"):
                t = Target(name, "--plot", force, inputs)
                old = os.getcwd()
                os.chdir(tmp_path)
                try:
                    write_text(t, "drawing")
                finally:
                    os.chdir(old)
    assert src.read_text() == "robot" and (tmp_path / "hard.yaml").read_text() == "robot"


def test_missing_folder_and_empty_name(tmp_path):
    with pytest.raises(InputError, match=r"the folder .*/no does not exist"):
        check_target(Target(str(tmp_path / "no" / "a.png")))
    with pytest.raises(InputError, match="^--plot: give a file name$"):
        check_target(Target("", "--plot"))


def test_a_failed_write_leaves_the_old_file_whole_and_no_temporary(tmp_path):
    f = tmp_path / "a.bin"
    f.write_bytes(b"old contents")
    with pytest.raises(RuntimeError):
        with replacing(Target(str(f), force=True)) as fh:
            fh.write(b"half a new fi")
            raise RuntimeError("the drawing failed")
    assert f.read_bytes() == b"old contents"
    assert os.listdir(tmp_path) == ["a.bin"]


def test_a_file_that_appears_meanwhile_is_not_overwritten(tmp_path):
    f = tmp_path / "a.txt"
    with pytest.raises(InputError, match="the file exists"):
        with replacing(Target(str(f)), binary=False) as fh:
            fh.write("ours")
            f.write_text("someone else's")        # between the check and the rename
    assert f.read_text() == "someone else's"
    assert os.listdir(tmp_path) == ["a.txt"]


def test_unwritable_folder_is_an_input_error(tmp_path):
    if os.geteuid() == 0:
        pytest.skip("root writes anywhere")
    d = tmp_path / "ro"
    d.mkdir()
    os.chmod(d, 0o555)
    try:
        with pytest.raises(InputError, match="cannot write in"):
            write_text(Target(str(d / "a.txt")), "x")
    finally:
        os.chmod(d, 0o755)


# --- every writer goes through it ------------------------------------------------------------

def run(argv, cwd):
    status, out, err = run_cli(argv, b"", str(cwd))
    assert_contract(status, out, err, argv)
    return status, out, err


@pytest.fixture()
def folder(tmp_path, umask022):
    """A robot file named robot.svg (the issue's case), an existing drawing and yaml."""
    (tmp_path / "robot.svg").write_bytes((ROOT / "robots" / "bk_rr.yaml").read_bytes())
    (tmp_path / "old.png").write_bytes(b"old drawing")
    (tmp_path / "old.yaml").write_text("old: file\n")
    (tmp_path / "old.html").write_text("old page")
    (tmp_path / "pose.txt").write_text("1 0 0 12\n0 1 0 2\n0 0 1 0\n0 0 0 1\n")
    (tmp_path / "link.png").symlink_to("old.png")
    return tmp_path


def _unchanged(folder):
    assert (folder / "robot.svg").read_bytes() == (ROOT / "robots" / "bk_rr.yaml").read_bytes()
    assert (folder / "old.png").read_bytes() == b"old drawing"
    assert (folder / "old.yaml").read_text() == "old: file\n"
    assert (folder / "old.html").read_text() == "old page"
    assert (folder / "link.png").is_symlink()
    assert not [p for p in os.listdir(folder) if p.startswith(".kincalc-")]


WRITERS = [
    # (command line writing to {out}, the option named in messages)
    (["plot", "robot.svg", "0", "0", "-o", "{out}", "--dpi", "10"], "-o"),
    (["ik", "robot.svg", "--xyz", "12", "2", "0", "--plot", "{out}", "--dpi", "10"], "--plot"),
    (["workspace", "robot.svg", "--samples", "1000", "--plot", "{out}", "--dpi", "10"],
     "--plot"),
    (["convert", "robot.svg", "--to", "dh", "-o", "{out}"], "-o"),
    (["quiz", "robot.svg", "--seed", "1", "--items", "fk", "-o", "{out}"], "--output"),
    (["view", "robot.svg", "0", "0", "-o", "{out}"], "-o"),
]
IDS = ["plot", "ik --plot", "workspace --plot", "convert", "quiz", "view"]
#: the suffix each writer's files have
SUFFIX = {"convert": ".yaml", "quiz": ".yaml", "view": ".html"}


def _argv(argv, out, *extra):
    return [a.replace("{out}", out) for a in argv] + list(extra)


def _existing(argv):
    return "old" + SUFFIX.get(argv[0], ".png")


#: every output option, file or folder: {out} is the name (a folder for the last two)
OUTPUTS = [argv for argv, _ in WRITERS] + [
    ["check", "sheet.yaml", "--format", "json", "-o", "{out}"],
    ["check", "sheet.yaml", "--gradebook", "{out}"],
    ["check", "sheet.yaml", "--feedback-dir", "{out}"],
    ["quiz", "robot.svg", "--roster", "roster.csv", "--salt", "s", "-o", "{out}"],
]


@pytest.mark.parametrize("argv", OUTPUTS, ids=" ".join)
def test_a_nul_in_an_output_name_is_bad_input(argv, folder):
    """No shell passes a NUL, but main() takes any list: a name holding one was an
    internal error (ValueError from the file system, exit 3)."""
    (folder / "sheet.yaml").write_bytes((ROOT / "examples" / "bk_example_4_2.yaml").read_bytes())
    (folder / "roster.csv").write_text("id\ns1\n")
    status, out, err = run(_argv(argv, "a\0b.png"), folder)
    assert status == 2 and "NUL character" in err and "\\x00" in err, err


@pytest.mark.parametrize("argv, option", WRITERS, ids=IDS)
def test_writer_refuses_its_own_robot_file_even_with_force(argv, option, folder):
    for force in ([], ["--force"]):
        status, out, err = run(_argv(argv, "robot.svg", *force), folder)
        assert status == 2 and out == "", err
        assert err == (f"kincalc: error: {option} robot.svg: that is the robot file, which "
                       "this command reads; kincalc never writes over its input\n"), err
    _unchanged(folder)


@pytest.mark.parametrize("argv, option", WRITERS, ids=IDS)
def test_writer_refuses_an_existing_file_without_force(argv, option, folder):
    name = _existing(argv)
    status, out, err = run(_argv(argv, name), folder)
    assert status == 2 and out == ""
    assert err == f"kincalc: error: {option} {name}: the file exists; use --force to " \
                  "overwrite it\n"
    _unchanged(folder)


@pytest.mark.parametrize("argv, option", WRITERS, ids=IDS)
def test_writer_force_replaces_no_device_and_no_link(argv, option, folder):
    # the case was /dev/null replaced by a root run; a FIFO is the device a test
    # can make (and a regression of this test cannot harm the machine it runs on)
    suffix = SUFFIX.get(argv[0], ".png")
    os.mkfifo(folder / f"pipe{suffix}")       # a FIFO opened for writing would block: never
    if suffix != ".png":
        os.symlink("old.yaml", folder / f"link{suffix}")
    for target, kind in ((f"pipe{suffix}", "a named pipe (FIFO)"),
                         (f"link{suffix}", "a symbolic link")):
        status, _, err = run(_argv(argv, target, "--force"), folder)
        assert status == 2 and f"is {kind}; kincalc replaces regular files only" in err, err
    assert stat.S_ISFIFO(os.lstat(folder / f"pipe{suffix}").st_mode)
    _unchanged(folder)


@pytest.mark.parametrize("argv, option", WRITERS, ids=IDS)
def test_writer_force_replaces_a_regular_file(argv, option, folder):
    name = _existing(argv)
    os.chmod(folder / name, 0o640)
    status, out, err = run(_argv(argv, name, "--force"), folder)
    assert status in (0, 1), err
    data = (folder / name).read_bytes()
    assert data not in (b"old drawing", b"old: file\n", b"old page") and data
    assert mode(folder / name) == 0o640                 # a replaced file keeps its mode
    assert not [p for p in os.listdir(folder) if p.startswith(".kincalc-")]


@pytest.mark.parametrize("argv, option", WRITERS, ids=IDS)
def test_writer_new_file_follows_the_umask(argv, option, folder):
    name = "new" + SUFFIX.get(argv[0], ".png")
    status, _, err = run(_argv(argv, name), folder)
    assert status in (0, 1), err
    assert mode(folder / name) == 0o644                  # convert wrote 0600
    _unchanged(folder)


def test_ik_plot_never_writes_over_its_pose_file(folder):
    for force in ([], ["--force"]):
        (folder / "pose.png").write_text("1 0 0 12\n0 1 0 2\n0 0 1 0\n0 0 0 1\n")
        status, _, err = run(["ik", "bk_rr", "--pose", "pose.png", "--plot", "pose.png",
                              *force], folder)
        assert status == 2 and "that is the --pose file" in err, err
        assert (folder / "pose.png").read_text().startswith("1 0 0 12")


def test_writer_checks_before_any_work(folder, monkeypatch):
    """A refused file costs nothing: workspace does not sample, convert does not
    convert, quiz does not draw, view does not load the robot."""
    import kincalc.cli.view
    import kincalc.conventions
    import kincalc.homework.quiz
    import kincalc.analysis.workspace

    def boom(*a, **k):
        raise AssertionError("work done before the output was checked")
    monkeypatch.setattr(kincalc.analysis.workspace, "analyse", boom)
    monkeypatch.setattr(kincalc.conventions, "convert", boom)
    monkeypatch.setattr(kincalc.homework.quiz, "make_sheet", boom)
    monkeypatch.setattr(kincalc.cli.view, "load_robot", boom)
    for argv, _ in WRITERS[2:]:
        status, _, err = run(_argv(argv, _existing(argv)), folder)
        assert status == 2 and "the file exists" in err, err


def test_a_file_read_while_recording_is_never_written(tmp_path):
    """Within limits.inputs_recorded (a command's run) a regular file read through
    open_input (read_bounded) is refused as an output, force or not, by any name of it;
    outside it (a script using the library) nothing is recorded."""
    from kincalc.limits import inputs_recorded, read_bounded
    src = tmp_path / "robot.yaml"
    src.write_text("robot")
    (tmp_path / "hard.yaml").hardlink_to(src)
    with inputs_recorded():
        read_bounded(str(src))
        for name in ("robot.yaml", "hard.yaml"):
            for force in (False, True):
                with pytest.raises(InputError, match="that is a file this command read"):
                    check_target(Target(str(tmp_path / name), "--gradebook", force))
        check_target(Target(str(tmp_path / "other.csv"), "--gradebook", False))
    check_target(Target(str(src), "--gradebook", True))
    assert src.read_text() == "robot"


@pytest.mark.parametrize("argv", [
    ["quiz", "puma560", "--roster", "roster.csv", "--salt", "x", "--items", "fk", "-o", "{long}"],
    ["check", "q.yaml", "--feedback-dir", "{long}"],
])
def test_a_folder_that_cannot_be_made_is_one_line(tmp_path, argv):
    """A folder name longer than the system allows (300 characters) for quiz --roster -o
    and check --feedback-dir was "internal error: OSError: File name too long" (an
    independent tester): now one line naming the option, exit 2."""
    long = "x" * 300
    (tmp_path / "roster.csv").write_text("id\ns1\n")
    assert run_cli(["quiz", "puma560", "--seed", "1", "-o", "q.yaml"], cwd=str(tmp_path))[0] == 0
    argv = [a.format(long=long) for a in argv]
    status, out, err = run_cli(argv, cwd=str(tmp_path))
    assert_contract(status, out, err, argv)
    assert status == 2 and err.count("\n") == 1
    assert "cannot make the folder" in err and argv[-2] in err


def test_make_folder_names_the_option(tmp_path):
    (tmp_path / "f").write_text("")
    with pytest.raises(InputError, match=r"^--feedback-dir .*f/sub: cannot make the folder"):
        outputs.make_folder(str(tmp_path / "f" / "sub"), "--feedback-dir")


def test_a_ctrl_c_while_a_file_is_written_leaves_no_temporary_file(tmp_path, python_ctrl_c):
    """Ctrl-C as ``quiz --roster -o DIR`` wrote its sheets left an empty ``.kincalc-XXXX.tmp``
    in 4 runs of 12 (fuzz campaign): the interrupt came between the temporary file's making
    and its naming or removal. It is taken once the file is written and named now: the file
    whole, no temporary file, and the KeyboardInterrupt after."""
    import signal
    target = tmp_path / "sheet.yaml"
    with pytest.raises(KeyboardInterrupt):
        with replacing(str(target)) as fh:
            fh.write(b"first half, ")
            os.kill(os.getpid(), signal.SIGINT)
            fh.write(b"second half")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["sheet.yaml"]
    assert target.read_bytes() == b"first half, second half"
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
