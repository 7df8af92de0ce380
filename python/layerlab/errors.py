"""The exceptions layerlab raises (the C++ layerlab::Error, translated)."""


class Error(RuntimeError):
    """A layerlab error: str() is the whole message, place first."""

    def __init__(self, what, file="", pointer="", message=None):
        super().__init__(what)
        self.file = file  # the input file, as it was named ("" when none)
        self.pointer = pointer  # RFC 6901 JSON pointer into it ("" is the whole document)
        self.message = what if message is None else message  # the part after the place


class SceneError(Error, ValueError):
    """Bad input at a place in a file: a scene (also one given as a dict, file
    "<dict>"), a target scene, a light-field manifest, measurements."""


class ArgumentError(Error, ValueError):
    """An argument refused by the check the command line makes of the same
    value (a target pixel that is not light, a pattern value outside [0, 1], a
    light-field geometry beyond a manifest's limits, a retina option, a solver
    option out of its range): str() names the argument and the offending index.
    A ValueError, so that `except ValueError` catches every bad argument."""


class Interrupted(KeyboardInterrupt):
    """Ctrl-C (SIGINT) stopped a solve between iterations; .solution holds the
    patterns of the last complete iteration (its report says "interrupted")."""

    def __init__(self, message, solution):
        super().__init__(message)
        self.solution = solution
