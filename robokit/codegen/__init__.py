"""Generated C99 for a robot's controller: FK, Jacobian, closed-form IK, gravity, inverse dynamics."""
from robokit.codegen.generate import C_KEYWORDS, CSource, c_name, generate_c, write_c

__all__ = ["CSource", "generate_c", "write_c", "c_name", "C_KEYWORDS"]
