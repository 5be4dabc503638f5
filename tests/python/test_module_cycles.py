"""scripts/module_cycles.py finds cycles among sibling modules and nothing else."""

from __future__ import annotations

import importlib.util
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
spec = importlib.util.spec_from_file_location("module_cycles", ROOT / "scripts" / "module_cycles.py")
assert spec and spec.loader
cycles_mod = importlib.util.module_from_spec(spec)
sys.modules[spec.name] = cycles_mod
spec.loader.exec_module(cycles_mod)


def crate(tmp_path: pathlib.Path, files: dict[str, str]) -> pathlib.Path:
    src = tmp_path / "src"
    for name, text in files.items():
        (src / name).parent.mkdir(parents=True, exist_ok=True)
        (src / name).write_text(text, encoding="utf-8")
    return src


def found(src):
    return [[m[-1] for m in comp] for comp in cycles_mod.cycles(cycles_mod.graph_of(src))]


def test_two_siblings_naming_each_other_are_a_cycle_through_use_trees_and_super(tmp_path) -> None:
    src = crate(tmp_path, {
        "lib.rs": "mod a; mod b; mod c;",
        "a.rs": "use crate::{b::Thing, c};",
        "b/mod.rs": "mod inner;",
        "b/inner.rs": "fn f() { super::super::a::g(); }",
        "c.rs": "",
    })
    assert found(src) == [["a", "b"]]


def test_a_parent_naming_its_child_and_back_is_no_cycle_nor_is_a_comment(tmp_path) -> None:
    src = crate(tmp_path, {
        "lib.rs": "mod a; mod b;",
        "a/mod.rs": "mod x; use self::x::Y; fn f() {}",
        "a/x.rs": "use super::f; // crate::b::Z in a comment\n/// [`crate::b::Z`]\nstruct Y;",
        "b.rs": "use crate::a::x::Y;",
    })
    assert found(src) == []


def test_a_sibling_named_through_a_reexport_is_a_dependency_where_it_is_defined(tmp_path) -> None:
    src = crate(tmp_path, {
        "lib.rs": "mod a; mod b; mod p; pub use b::Thing;",
        "a.rs": "use crate::Thing;\npub fn f() {}",
        "b.rs": "pub struct Thing;\nfn g() { crate::a::f(); }",
        "p/mod.rs": "mod x; mod y; mod z; pub use y::{Y as Why, self as yy};",
        "p/x.rs": "use super::Why; pub struct X;",
        "p/y.rs": "use super::x::X; pub struct Y;",
        "p/z.rs": "fn h() { super::yy::Y; }",
        "main.rs": "use crate::Thing;",
    })
    assert found(src) == [["a", "b"], ["x", "y"]]


def test_an_import_of_another_crate_or_a_parents_own_item_adds_no_edge(tmp_path) -> None:
    src = crate(tmp_path, {
        "lib.rs": "mod a; mod b; pub use serde::Serialize; pub struct Root;",
        "a.rs": "use crate::{Serialize, Root}; pub fn f() {}",
        "b.rs": "fn g() { crate::a::f(); }",
    })
    assert found(src) == []


def test_the_tree_has_no_module_cycle() -> None:
    assert cycles_mod.all_cycles() == []
