"""The streamed validate table stays aligned whatever the length of a quantity's name."""
from robokit.validation import _WIDTHS, _line


def test_long_quantities_wrap_and_the_columns_stay_aligned():
    names = ["short", "x" * _WIDTHS[0], "DH propagation Jacobian (base) vs computeFrameJacobian (LOCAL_WORLD_ALIGNED)",
             "a name with a_very_long_unbroken_token_" + "y" * 80 + " and more"]
    rows = [_line((q, "puma560", "100", "1.20e-15", "1e-09", "rel, max entry", "ok")) for q in names]
    header = _line(("quantity", "model", "cases", "max error", "tol", "metric", "pass"))
    model_col = header.index("model")
    for text, q in zip(rows, names):
        *lead, last = text.split("\n")
        assert last.index("puma560") == model_col, text
        assert all(len(x) <= _WIDTHS[0] for x in lead)
        # nothing of the name is lost
        assert "".join(x.strip() for x in [*lead, last[:model_col]]).replace(" ", "") == q.replace(" ", "")
