"""``python -m robokit.kernels``: compile every course kernel ahead of first use (see :mod:`robokit.kernels.warm`)."""
import sys

from robokit.kernels.warm import main

sys.exit(main())
