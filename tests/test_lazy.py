"""The lazy module stand-in: imports at the first use, then costs a plain lookup."""

import importlib
import sys

from lineload.runtime import lazy


def test_the_stand_in_imports_at_first_use_and_keeps_what_it_found(monkeypatch):
    name = "json"  # a standard module: the test controls when it is imported
    monkeypatch.delitem(sys.modules, name, raising=False)
    calls = []
    real = importlib.import_module

    def counting(module_name, *args):
        calls.append(module_name)
        return real(module_name, *args)

    monkeypatch.setattr(lazy.importlib, "import_module", counting)
    stand_in = lazy.lazy_import(name)
    assert name not in sys.modules and calls == []  # nothing imported yet
    assert stand_in.dumps([1]) == "[1]"
    assert name in sys.modules and calls == [name]
    for _ in range(3):
        assert stand_in.dumps is sys.modules[name].dumps
    stand_in.loads("2")
    assert calls == [name, name]  # once per name, not once per access
