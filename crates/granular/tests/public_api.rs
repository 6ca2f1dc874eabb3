//! The library's public surface, compared with the checked-in list `tests/public_api.txt`,
//! so that its growth is a decision (docs/library.md).
//!
//! The list is made by walking the crate's module tree from `src/lib.rs` with `syn` (no
//! nightly rustdoc needed): every module reachable through `pub mod`, and in each the items
//! declared `pub` (functions, types, traits, constants, statics, exported macros), the
//! `pub fn` of inherent `impl` blocks (as `Type::method`) and the `pub use` re-exports (as
//! written). `pub(crate)`, `pub(super)` and `pub(in ..)` are not public; `#[cfg(test)]` is
//! skipped; `#[doc(hidden)]` items are listed with ` (hidden)`.
//!
//! After an intended change of the surface, rewrite the list and commit it:
//! `GRANULAR_BLESS_PUBLIC_API=1 cargo test --release -p granular --test physics -- public_api`.

use quote::ToTokens;
use std::path::{Path, PathBuf};
use syn::{Attribute, ImplItem, Item, UseTree, Visibility};

/// The checked-in list.
const LIST: &str = "tests/public_api.txt";

#[test]
fn public_api_is_the_checked_in_list() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let found = public_items(&root.join("src"));
    let list_path = root.join(LIST);
    let text = found.join("\n") + "\n";
    if std::env::var_os("GRANULAR_BLESS_PUBLIC_API").is_some() {
        std::fs::write(&list_path, &text).expect("writing tests/public_api.txt");
        return;
    }
    let expected = std::fs::read_to_string(&list_path).unwrap_or_default();
    let expected: Vec<&str> = expected.lines().filter(|l| !l.is_empty()).collect();
    let added: Vec<&String> = found
        .iter()
        .filter(|l| !expected.contains(&l.as_str()))
        .collect();
    let removed: Vec<&&str> = expected
        .iter()
        .filter(|l| !found.iter().any(|f| f == **l))
        .collect();
    assert!(
        added.is_empty() && removed.is_empty(),
        "the public surface of the granular crate changed.\n\
         new public items ({}):\n  {}\n\
         items no longer public ({}):\n  {}\n\
         Keep new items pub(crate) unless a user needs them; if the change is intended, \
         rewrite the list with\n  GRANULAR_BLESS_PUBLIC_API=1 cargo test --release -p granular \
         --test physics -- public_api\nand commit crates/granular/{LIST}.",
        added.len(),
        added
            .iter()
            .map(|s| s.as_str())
            .collect::<Vec<_>>()
            .join("\n  "),
        removed.len(),
        removed.iter().map(|s| **s).collect::<Vec<_>>().join("\n  "),
    );
}

/// The walker finds what it should in a small module tree.
#[test]
fn public_api_walker_sees_what_is_public() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let src = dir.path();
    std::fs::write(
        src.join("lib.rs"),
        "pub mod a; mod b; pub use b::Thing; pub(crate) fn hidden() {}\n\
         #[doc(hidden)] pub mod c { pub fn f() {} }\n\
         #[cfg(test)] mod tests { pub fn t() {} }\n\
         #[macro_export] macro_rules! m { () => {} }\n",
    )
    .expect("write");
    std::fs::create_dir(src.join("a")).expect("mkdir");
    std::fs::write(
        src.join("a/mod.rs"),
        "pub struct S; impl S { pub fn new() -> S { S } fn private(&self) {} \
         pub(crate) fn inner(&self) {} pub const K: u8 = 1; }\n\
         pub mod d; pub enum E { X } pub trait T {} impl T for S {}\n\
         pub(super) fn no() {} pub type Alias = S; pub const C: f64 = 1.0;\n",
    )
    .expect("write");
    std::fs::write(
        src.join("a/d.rs"),
        "pub static ST: u8 = 0; fn private() {}\n",
    )
    .expect("write");
    std::fs::write(
        src.join("b.rs"),
        "pub struct Thing; impl Thing { pub fn go() {} } struct P; impl P { pub fn x() {} }\n",
    )
    .expect("write");
    let items = public_items(src);
    assert_eq!(
        items,
        [
            "const S::K",
            "const crate::a::C",
            "enum crate::a::E",
            "fn S::new",
            "fn Thing::go",
            "fn crate::c::f (hidden)",
            "macro crate::m",
            "mod crate::a",
            "mod crate::a::d",
            "mod crate::c (hidden)",
            "static crate::a::d::ST",
            "struct crate::a::S",
            "trait crate::a::T",
            "type crate::a::Alias",
            "use crate: b::Thing",
        ]
    );
}

/// The sorted public items of the crate whose `lib.rs` is in `src`.
fn public_items(src: &Path) -> Vec<String> {
    let mut walk = Walk::default();
    walk.module(&parse(&src.join("lib.rs")), "crate", src, true, false);
    let mut out = walk.items;
    for (ty, member) in walk.members {
        if walk.types.contains(&ty) {
            out.push(member);
        }
    }
    out.sort();
    out.dedup();
    out
}

/// What the walk has found.
#[derive(Default)]
struct Walk {
    /// The public items, as listed.
    items: Vec<String>,
    /// The names of the public types (declared in a public module or re-exported).
    types: Vec<String>,
    /// The `pub` members of inherent `impl` blocks, with their type's name (in any module:
    /// an `impl` block in a private module adds methods to a public type).
    members: Vec<(String, String)>,
}

fn parse(path: &Path) -> Vec<Item> {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    syn::parse_file(&text)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .items
}

fn is_pub(vis: &Visibility) -> bool {
    matches!(vis, Visibility::Public(_))
}

fn has_attr(attrs: &[Attribute], name: &str, arg: &str) -> bool {
    attrs
        .iter()
        .any(|a| a.path().is_ident(name) && a.meta.to_token_stream().to_string().contains(arg))
}

fn is_test_only(attrs: &[Attribute]) -> bool {
    attrs
        .iter()
        .any(|a| a.path().is_ident("cfg") && a.meta.to_token_stream().to_string() == "cfg (test)")
}

fn suffix(hidden: bool) -> &'static str {
    if hidden { " (hidden)" } else { "" }
}

impl Walk {
    /// Walks the module `path` (its items `items`; its submodules' files under `dir`);
    /// `public`: reachable from outside the crate; `hidden`: under `#[doc(hidden)]`.
    fn module(&mut self, items: &[Item], path: &str, dir: &Path, public: bool, hidden: bool) {
        for item in items {
            if let Item::Impl(i) = item
                && i.trait_.is_none()
                && !is_test_only(&i.attrs)
            {
                self.impl_members(i, hidden);
            }
            if let Item::Mod(m) = item
                && !is_test_only(&m.attrs)
            {
                self.submodule(m, path, dir, public, hidden);
            }
            if public {
                self.item(item, path, hidden);
            }
        }
    }

    fn submodule(&mut self, m: &syn::ItemMod, path: &str, dir: &Path, public: bool, hidden: bool) {
        let name = m.ident.to_string();
        let public = public && is_pub(&m.vis);
        let hidden = hidden || has_attr(&m.attrs, "doc", "hidden");
        let sub_path = format!("{path}::{name}");
        match &m.content {
            Some((_, items)) => self.module(items, &sub_path, &dir.join(&name), public, hidden),
            None => {
                let (file, sub_dir) = module_file(dir, &name);
                self.module(&parse(&file), &sub_path, &sub_dir, public, hidden);
            }
        }
    }

    fn impl_members(&mut self, block: &syn::ItemImpl, hidden: bool) {
        let ty = type_name(&block.self_ty);
        let hidden = hidden || has_attr(&block.attrs, "doc", "hidden");
        for member in &block.items {
            let (kind, name, attrs) = match member {
                ImplItem::Fn(f) if is_pub(&f.vis) => ("fn", &f.sig.ident, &f.attrs),
                ImplItem::Const(c) if is_pub(&c.vis) => ("const", &c.ident, &c.attrs),
                _ => continue,
            };
            let hidden = hidden || has_attr(attrs, "doc", "hidden");
            self.members
                .push((ty.clone(), format!("{kind} {ty}::{name}{}", suffix(hidden))));
        }
    }

    /// Records `item` of the public module `path` when it is public.
    fn item(&mut self, item: &Item, path: &str, hidden: bool) {
        let (kind, ident, attrs, vis) = match item {
            Item::Fn(f) => ("fn", &f.sig.ident, &f.attrs, &f.vis),
            Item::Struct(s) => ("struct", &s.ident, &s.attrs, &s.vis),
            Item::Enum(e) => ("enum", &e.ident, &e.attrs, &e.vis),
            Item::Union(u) => ("union", &u.ident, &u.attrs, &u.vis),
            Item::Trait(t) => ("trait", &t.ident, &t.attrs, &t.vis),
            Item::Type(t) => ("type", &t.ident, &t.attrs, &t.vis),
            Item::Const(c) => ("const", &c.ident, &c.attrs, &c.vis),
            Item::Static(s) => ("static", &s.ident, &s.attrs, &s.vis),
            Item::Mod(m) => ("mod", &m.ident, &m.attrs, &m.vis),
            Item::Macro(m) => {
                if let (true, Some(ident)) = (has_attr(&m.attrs, "macro_export", ""), &m.ident) {
                    self.items.push(format!("macro crate::{ident}"));
                }
                return;
            }
            Item::Use(u) => {
                if is_pub(&u.vis) {
                    let hidden = hidden || has_attr(&u.attrs, "doc", "hidden");
                    let mut leaves = Vec::new();
                    use_paths(&u.tree, String::new(), &mut leaves);
                    for (leaf, name) in leaves {
                        self.items
                            .push(format!("use {path}: {leaf}{}", suffix(hidden)));
                        self.types.push(name);
                    }
                }
                return;
            }
            _ => return,
        };
        if !is_pub(vis) || is_test_only(attrs) {
            return;
        }
        let hidden = hidden || has_attr(attrs, "doc", "hidden");
        self.items
            .push(format!("{kind} {path}::{ident}{}", suffix(hidden)));
        if matches!(kind, "struct" | "enum" | "union" | "trait" | "type") {
            self.types.push(ident.to_string());
        }
    }
}

/// The file of the module `name` declared in a module whose submodules live in `dir`, and
/// the folder of its own submodules.
fn module_file(dir: &Path, name: &str) -> (PathBuf, PathBuf) {
    let flat = dir.join(format!("{name}.rs"));
    if flat.is_file() {
        (flat, dir.join(name))
    } else {
        (dir.join(name).join("mod.rs"), dir.join(name))
    }
}

/// The paths named by a `use` tree (`self::`/`super::`/`crate::` as written), each with the
/// name it is seen by.
fn use_paths(tree: &UseTree, prefix: String, out: &mut Vec<(String, String)>) {
    let join = |name: &str| {
        if prefix.is_empty() {
            name.to_string()
        } else {
            format!("{prefix}::{name}")
        }
    };
    match tree {
        UseTree::Path(p) => use_paths(&p.tree, join(&p.ident.to_string()), out),
        UseTree::Name(n) => out.push((join(&n.ident.to_string()), n.ident.to_string())),
        UseTree::Rename(r) => out.push((
            format!("{} as {}", join(&r.ident.to_string()), r.rename),
            r.rename.to_string(),
        )),
        UseTree::Glob(_) => out.push((join("*"), String::new())),
        UseTree::Group(g) => {
            for t in &g.items {
                use_paths(t, prefix.clone(), out)
            }
        }
    }
}

/// The name of an `impl` block's type without its generic arguments (`Edmd`, not
/// `Edmd<D>`).
fn type_name(ty: &syn::Type) -> String {
    match ty {
        syn::Type::Path(p) => p
            .path
            .segments
            .last()
            .map(|s| s.ident.to_string())
            .unwrap_or_default(),
        other => other.to_token_stream().to_string(),
    }
}
