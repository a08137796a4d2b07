# The Python package se3_interpolation (src/se3_interpolation), installed by catkin_python_setup()
# into the devel and install spaces beside the generated messages; its compiled core, _core, is
# built and installed by CMakeLists.txt.
from catkin_pkg.python_setup import generate_distutils_setup
from setuptools import setup

setup(**generate_distutils_setup(packages=["se3_interpolation"], package_dir={"": "src"}))
