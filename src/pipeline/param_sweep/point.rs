//! The scene of one sweep point: the base scene's text with each swept key's value replaced
//! (comments, layout and line numbers kept, so an error in a point names the line of the
//! file), then parsed and validated like any scene.

use super::Design;
use crate::error::{Error, SpecError};
use crate::spec::Scene;
use crate::spec::sweep::{Target, find, target};

/// The scene of point `p` of `design`, or the loader's error at that point.
pub fn scene(base: &Scene, design: &Design, p: usize) -> Result<Scene, Error> {
    let text = text(base, design, p)?;
    Scene::parse(&base.path, &text).map_err(|e| {
        Error::Spec(SpecError {
            message: format!("{} (sweep point {p}: {})", e.message, describe(design, p)),
            ..e
        })
    })
}

/// `key = value, …` of point `p`.
pub fn describe(design: &Design, p: usize) -> String {
    design
        .keys
        .iter()
        .zip(&design.points[p])
        .map(|(k, v)| format!("{k} = {v}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The base text with point `p`'s values written in.
fn text(base: &Scene, design: &Design, p: usize) -> Result<String, Error> {
    let mut doc: toml_edit::DocumentMut = base
        .text
        .parse()
        .map_err(|e| Error::Other(format!("{}: {e}", base.path.display())))?;
    for (key, &v) in design.keys.iter().zip(&design.points[p]) {
        let bad = |why: String| Error::Other(format!("{}: sweep key {why}", base.path.display()));
        let new = match target(doc.as_item(), key).map_err(bad)? {
            Target::Integer(_) => toml_edit::Value::from(v as i64),
            Target::Float(_) => toml_edit::Value::from(v),
        };
        let slot = find_mut(doc.as_item_mut(), key).map_err(bad)?;
        let decor = slot.decor().clone();
        *slot = new;
        *slot.decor_mut() = decor;
    }
    Ok(doc.to_string())
}

/// The value at `key`, for writing (its existence and type were checked by [`target`]).
fn find_mut<'a>(
    root: &'a mut toml_edit::Item,
    key: &str,
) -> Result<&'a mut toml_edit::Value, String> {
    // Walk read-only first for the error message, then mutably along the same path.
    find(root, key)?;
    let mut item = root;
    for (name, index) in crate::spec::split_path(key) {
        item = item
            .get_mut(name.as_str())
            .ok_or_else(|| format!("`{key}`: no `{name}`"))?;
        if let Some(i) = index {
            item = item
                .get_mut(i)
                .ok_or_else(|| format!("`{key}`: no element {i}"))?;
        }
    }
    item.as_value_mut()
        .ok_or_else(|| format!("`{key}` is not a value"))
}
