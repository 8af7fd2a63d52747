"""``python -m course_dynamics.cli``: the same as the ``course-dynamics`` command."""
import sys

from . import main

sys.exit(main())
