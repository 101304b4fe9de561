"""Python: the closed form as plain float64 math, used to test the derivation numerically."""

from codegen.dialects import Dialect


class Python(Dialect):
    """No controller runs it: a printer only, no grammar and no interpreter."""

    name = "python"
