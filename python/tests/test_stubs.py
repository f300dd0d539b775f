"""The shipped stubs (python/toolpoint/__init__.pyi) against the live module: the same public names,
the same members of each class, and for every function, method and overload the same parameters
(name, positional or keyword-only, with or without a default), read from the module's own
introspection (pybind11's signature lines; inspect.signature for the Options constructors that
toolpoint/__init__.py defines). A name or parameter added, removed or renamed in the bindings
without regenerating the stubs (python/packaging/make_stubs.py) fails here, so they cannot go stale.
"""
import ast
import inspect
import re

import pytest

import toolpoint as tp

from conftest import SOURCE_DIR

STUB = SOURCE_DIR / "python" / "toolpoint" / "__init__.pyi"
TREE = ast.parse(STUB.read_text())


def split_params(text):
    """Top-level comma split (brackets and quotes kept whole)."""
    out, depth, quote, cur = [], 0, None, ""
    for ch in text:
        if quote:
            quote = None if ch == quote else quote
        elif ch in "'\"":
            quote = ch
        elif ch in "([{<":
            depth += 1
        elif ch in ")]}>":
            depth -= 1
        if ch == "," and depth == 0 and not quote:
            out.append(cur.strip())
            cur = ""
        else:
            cur += ch
    return [p for p in [*out, cur.strip()] if p]


def live_signatures(obj, name):
    """[(name, kind, has_default), ...] per overload, self left out; kind 'pos' or 'kw'."""
    sigs = []
    for line in (obj.__doc__ or "").splitlines():
        m = re.match(r"^\s*(?:\d+\. )?" + re.escape(name) + r"\((.*)\)(?: -> .+)?$", line)
        if not m or "*args, **kwargs" in m.group(1):
            continue
        params, kind = [], "pos"
        for p in split_params(m.group(1)):
            if p == "*":
                kind = "kw"
            elif p != "/":
                pname = p.split(":")[0].strip()
                if pname != "self":
                    params.append((pname, kind, "=" in p))
        sigs.append(params)
    if not sigs:  # a Python-level function (the Options constructors)
        s = inspect.signature(obj)
        sigs.append([(p.name, "kw" if p.kind == p.KEYWORD_ONLY else "pos", p.default is not p.empty)
                     for p in s.parameters.values() if p.name != "self"])
    return sigs


def stub_signature(fn):
    a = fn.args
    pos = a.posonlyargs + a.args
    defaults = [False] * (len(pos) - len(a.defaults)) + [True] * len(a.defaults)
    params = [(p.arg, "pos", d) for p, d in zip(pos, defaults) if p.arg != "self"]
    params += [(p.arg, "kw", d is not None) for p, d in zip(a.kwonlyargs, a.kw_defaults)]
    return params


def stub_members(body):
    """name -> list of signatures (functions, overloads) or 'attribute'."""
    members = {}
    for node in body:
        if isinstance(node, ast.FunctionDef):
            is_property = any(isinstance(d, ast.Name) and d.id == "property" for d in node.decorator_list)
            if is_property:
                members[node.name] = "attribute"
            else:
                members.setdefault(node.name, []).append(stub_signature(node))
        elif isinstance(node, ast.AnnAssign):
            members[node.target.id] = "attribute"
        elif isinstance(node, ast.ClassDef):
            members[node.name] = node
    return members


STUBBED = stub_members(TREE.body)
PUBLIC = sorted(n for n in tp.__all__ if n != "__version__")


def test_the_stubs_name_every_public_name_and_no_other():
    assert set(STUBBED) - {"__version__"} == set(PUBLIC)
    assert "__version__" in STUBBED


@pytest.mark.parametrize("name", PUBLIC)
def test_each_name_matches_its_stub(name):
    live, stub = getattr(tp, name), STUBBED[name]
    if not isinstance(live, type):
        assert stub == live_signatures(live, name), f"{name}: stub {stub} against live"
        return
    assert isinstance(stub, ast.ClassDef), f"{name} is a class"
    if issubclass(live, BaseException):
        assert [b.id for b in stub.bases] == [b.__name__ for b in live.__bases__]
        return
    members = stub_members(stub.body)
    public = {a: v for a, v in vars(live).items() if not a.startswith("_")}
    init = vars(live).get("__init__")
    if init is not None and not (init.__doc__ or "").startswith("Initialize self."):  # a constructor
        public["__init__"] = init
    assert set(members) == set(public), f"{name}: members differ"
    for attr, value in public.items():
        if isinstance(value, property):
            assert members[attr] == "attribute", f"{name}.{attr} is a property"
        else:
            func = value.__func__ if isinstance(value, staticmethod) else value
            assert members[attr] == live_signatures(func, attr), f"{name}.{attr}: stub {members[attr]} against live"
