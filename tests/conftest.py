import sys
from pathlib import Path

from hypothesis import settings

sys.path.insert(0, str(Path(__file__).parent))

# Every hypothesis test draws the same examples on every run and machine (issue 14: a
# seeded test must draw the same cases every time); no example database on disk.
settings.register_profile("kincalc", derandomize=True, database=None, deadline=None)
settings.load_profile("kincalc")
