"""Bad arguments to the package's functions as one-line TypeErrors that name the valid keywords.

pybind11 answers a call it cannot match with a multi-line TypeError listing signatures, and
Python with "f() got an unexpected keyword argument 'x'" alone. Every public function, method
and constructor of the package is wrapped (physik/__init__.py, physik/sweep.py) so that
    solve() got an unexpected keyword argument 'tole'; valid: scene, solver, tol, ...
    Scene.load(): bad arguments (float); expected (path: str, overrides: object = None, ...)
A call that matches runs as before; only the failed match is reworded. The parameter names of a
compiled function come from the signature line pybind11 writes at the top of its docstring.
"""
import functools
import inspect
import re

_PYBIND_MISMATCH = "incompatible function arguments"


def _split_top_level(text):
    """Split a parameter list at the commas outside brackets and quotes."""
    parts, depth, quote, start = [], 0, None, 0
    for i, ch in enumerate(text):
        if quote:
            quote = None if ch == quote else quote
        elif ch in "'\"":
            quote = ch
        elif ch in "([{":
            depth += 1
        elif ch in ")]}":
            depth -= 1
        elif ch == "," and depth == 0:
            parts.append(text[start:i].strip())
            start = i + 1
    parts.append(text[start:].strip())
    return [p for p in parts if p]


def pybind_signature(fn):
    """(the parameter text, [names]) of a compiled function, from its docstring's first line
    "name(a: T, b: T = d) -> R" (self, * and / left out of the names)."""
    first = (fn.__doc__ or "").lstrip().split("\n", 1)[0]
    m = re.match(r"^\w+\((.*)\) -> .*$", first)
    if not m:
        raise ValueError("no pybind11 signature line in the docstring of %r" % fn)
    params = [p for p in _split_top_level(m.group(1)) if not p.startswith("self")]
    names = [p.split(":")[0].split("=")[0].strip() for p in params]
    return ", ".join(params), [n for n in names if n not in ("*", "/")]


def _unexpected(name, names, kwargs):
    for key in kwargs:
        if key not in names:
            valid = "valid: " + ", ".join(names) if names else "it takes no arguments"
            return "%s() got an unexpected keyword argument '%s'; %s" % (name, key, valid)
    return None


def _described(args, kwargs):
    """The arguments of a call by type, as "(str, float, steps=str)"."""
    items = [type(a).__name__ for a in args]
    items += ["%s=%s" % (k, type(v).__name__) for k, v in kwargs.items()]
    return "(" + ", ".join(items) + ")"


def compiled(fn, name, bound=False):
    """A pybind11 function (or method, bound: its first argument is self) whose failed match
    raises a one-line TypeError."""
    params, names = pybind_signature(fn)

    @functools.wraps(fn)
    def call(*args, **kwargs):
        try:
            return fn(*args, **kwargs)
        except TypeError as e:
            if _PYBIND_MISMATCH not in str(e):
                raise
            shown = args[1:] if bound else args
            message = _unexpected(name, names, kwargs) or \
                "%s(): bad arguments %s; expected (%s)" % (name, _described(shown, kwargs), params)
            raise TypeError(message) from None
    return call


def python(fn, name):
    """A Python function whose call that does not match its signature raises a one-line
    TypeError naming the valid keywords (a TypeError from inside the function passes as is)."""
    signature = inspect.signature(fn)
    names = [p for p in signature.parameters if p != "self"]

    @functools.wraps(fn)
    def call(*args, **kwargs):
        try:
            return fn(*args, **kwargs)
        except TypeError as e:
            try:
                signature.bind(*args, **kwargs)
            except TypeError:
                message = _unexpected(name, names, kwargs) or "%s(): %s; valid: %s" % (
                    name, re.sub(r"^[\w.]+\(\) ", "", str(e)), ", ".join(names))
                raise TypeError(message) from None
            raise
    return call


def wrap_class(cls, names, title=None):
    """Wrap the methods `names` of `cls` in place (compiled or Python, static or not);
    "__init__" is named after the class, the others as Class.method."""
    title = title or cls.__name__
    for attr in names:
        raw = cls.__dict__[attr]
        name = title if attr == "__init__" else "%s.%s" % (title, attr)
        if isinstance(raw, staticmethod):
            fn = raw.__func__
            wrapped = python(fn, name) if inspect.isfunction(fn) else compiled(fn, name)
            setattr(cls, attr, staticmethod(wrapped))
        elif inspect.isfunction(raw):
            setattr(cls, attr, python(raw, name))
        else:  # a pybind11 instancemethod: the function it holds takes self first
            setattr(cls, attr, compiled(raw.__func__, name, bound=True))
