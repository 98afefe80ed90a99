"""Bad IK and selftest command lines: one line on stderr, exit 2, nothing on stdout."""

import pytest

from kincalc.cli.main import main

CASES = [
    (["ik", "puma560", "--xyz", "0.5", "0", "0.3", "--quat", "0", "0", "0", "0"], "zero quaternion"),
    (["ik", "puma560", "--xyz", "0.5", "0", "0.3", "--matrix", *"1 0 0 0 1 0 0 0 2".split()],
     "not a rotation matrix"),
    (["ik", "puma560", "--pose", "/nonexistent/pose.txt"], "cannot read"),
    (["ik", "puma560", "--xyz", "0.5", "0", "0.3"], "give an orientation too"),
    # the ways a target can give it: --tcv only for a robot that takes one
    (["ik", "puma560", "--xyz", "0.5", "0", "0.3"], "--matrix, --pose or --from-q)"),
    (["ik", "fer_rrpr", "--xyz", "0.5", "0", "0.3"],
     "--pose or --from-q) or a tool configuration vector (--tcv)"),
    (["ik", "puma560", "--xyz", "0.5", "0", "0.3", "--rpy", "0", "0", "0", "--quat", "1", "0", "0", "0"],
     "at most one orientation"),
    (["ik", "iiwa7", "--xyz", "0.5", "0", "0.3", "--near", "1 2"], "--near: iiwa7 has 7 joints"),
    (["ik", "puma560", "--from-q", "0 0 0 0 0 0", "--near", "0 0 x 0 0 0"],
     "--near: joint value 'x' is not a number"),
    (["ik", "puma560", "--xyz", "0.5", "0", "0.3", "--approach", "0", "0", "1"],
     "--approach: puma560 controls position and orientation"),
    (["ik", "puma560", "--xyz", "0.5", "0", "0.3", "--approach", "0", "0", "0"],
     "--approach must not be the zero vector"),
    (["ik", "puma560", "--xyz", "0.5", "0", "0.3", "--approach", "0", "0", "1", "--rpy", "0", "0",
      "0"], "at most one orientation"),
    (["ik", "iiwa7", "--xyz", "0.5", "0", "0.3", "--approach", "0", "0", "1"],
     "--approach: iiwa7 is solved numerically"),
    (["ik", "puma560", "--from-q", "1 2"], "has 6 joints"),
    # an empty value between commas is not dropped (a fuzz campaign: 7 values were 6)
    (["ik", "puma560", "--from-q", "10,,20,30,40,50,60"], "--from-q: value 2 is empty"),
    (["ik", "puma560", "--from-q", "10,20,30,40,50,60,"], "--from-q: value 7 is empty"),
    (["reach", "puma560", "--from-q", ",10,20,30,40,50,60"], "--from-q: value 1 is empty"),
    (["ik", "puma560", "--from-q", "0 0 0 0 0 0", "--near", "1,,2,3,4,5"],
     "--near: value 2 is empty"),
    (["ik", "puma560", "--tcv", "1", "2", "3", "0", "0", "1"], "--tcv targets need"),
    (["ik", "puma560", "--from-q", "0 0 0 0 0 0", "--xyz", "1", "0", "0"], "whole pose"),
    (["ik", "puma560", "--rpy", "0", "0", "0"], "--xyz"),
    (["ik", "bk_rr", "--xyz", "1", "2"], "requires 3 arguments"),
    (["selftest", "bk_rr", "--seed", "-1"], "--seed"),
    (["selftest", "bk_rr", "--trials", "0"], "--trials"),
]


@pytest.mark.parametrize("argv,fragment", CASES, ids=[" ".join(c[0][:4]) + f" #{i}" for i, c in enumerate(CASES)])
def test_bad_ik_input(argv, fragment, capsys):
    code = main(argv)
    out, err = capsys.readouterr()
    assert code == 2
    assert out == ""
    lines = [line for line in err.splitlines() if line.strip()]
    assert len(lines) == 1 and "Traceback" not in err
    assert fragment in lines[0]
