"""The package's one compiled part: the native loop (course_dynamics/core/compiled/looped.c), built where a C
compiler exists. It is optional: without a compiler the install still succeeds and the recursions as written
run. The C is generated from the library's recursions (course_dynamics.core.compiled.steps.c_source) and
shipped; a test holds it to what they generate now. Everything else is in pyproject.toml."""
from setuptools import Extension, setup

setup(ext_modules=[Extension("course_dynamics.core.compiled._looped", ["course_dynamics/core/compiled/looped.c"],
                             extra_compile_args=["-O2", "-fno-math-errno", "-ffp-contract=off"], optional=True)])
