//! The `gltf` crate's validation as errors naming a JSON pointer, and the extension checks.

use super::{Ctx, SUPPORTED_EXTENSIONS};
use crate::error::Result;
use gltf::json::validation::{Error as VError, Validate};

/// `meshes[0].primitives[0].attributes["POSITION"]` (the `gltf` crate's path) as the JSON
/// pointer `/meshes/0/primitives/0/attributes/POSITION`.
pub(super) fn json_pointer(path: &str) -> String {
    let path = path.split(" = ").next().unwrap_or(path);
    let mut out = String::new();
    let mut rest = path;
    while !rest.is_empty() {
        if let Some(r) = rest.strip_prefix('.') {
            rest = r;
            continue;
        }
        if let Some(r) = rest.strip_prefix("[\"") {
            let end = r.find("\"]").unwrap_or(r.len());
            push(&mut out, &r[..end]);
            rest = r.get(end + 2..).unwrap_or("");
        } else if let Some(r) = rest.strip_prefix('[') {
            let end = r.find(']').unwrap_or(r.len());
            push(&mut out, &r[..end]);
            rest = r.get(end + 1..).unwrap_or("");
        } else {
            let end = rest.find(['.', '[']).unwrap_or(rest.len());
            push(&mut out, &rest[..end]);
            rest = &rest[end..];
        }
    }
    out
}

/// Appends one reference token, escaped (`~0`, `~1`).
fn push(out: &mut String, token: &str) {
    out.push('/');
    out.push_str(&token.replace('~', "~0").replace('/', "~1"));
}

/// What an index at the end of `ptr` refers to: (the singular, the top-level array).
fn refers_to(ptr: &str) -> Option<(&'static str, &'static str)> {
    let parts: Vec<&str> = ptr.split('/').collect();
    let last = parts.iter().rev().find(|p| p.parse::<usize>().is_err())?;
    let parent = parts.len().checked_sub(2).map(|i| parts[i]);
    Some(match *last {
        "indices" | "inverseBindMatrices" | "input" | "output" => ("accessor", "accessors"),
        _ if parent == Some("attributes") || parts.contains(&"targets") => {
            ("accessor", "accessors")
        }
        "bufferView" => ("buffer view", "bufferViews"),
        "buffer" => ("buffer", "buffers"),
        "mesh" => ("mesh", "meshes"),
        "material" => ("material", "materials"),
        "children" | "nodes" | "node" | "joints" | "skeleton" => ("node", "nodes"),
        "camera" => ("camera", "cameras"),
        "skin" => ("skin", "skins"),
        "scene" => ("scene", "scenes"),
        "source" => ("image", "images"),
        "sampler" => ("sampler", "samplers"),
        "index" => ("texture", "textures"),
        _ => return None,
    })
}

/// Runs the `gltf` crate's validation; the first problem becomes an error naming its JSON
/// pointer (and for an index out of range, what it names and how many there are).
pub(super) fn validate(ctx: &Ctx, root: &gltf::json::Root, raw: &serde_json::Value) -> Result<()> {
    // The crate's primitive check indexes the POSITION accessor without a bound check: out of
    // range, it would panic, so that index is checked here first.
    for (i, m) in root.meshes.iter().enumerate() {
        for (j, p) in m.primitives.iter().enumerate() {
            let pos = gltf::json::validation::Checked::Valid(gltf::Semantic::Positions);
            if let Some(a) = p.attributes.get(&pos)
                && a.value() >= root.accessors.len()
            {
                return Err(ctx.err(
                    &format!("/meshes/{i}/primitives/{j}/attributes/POSITION"),
                    format!(
                        "accessor {} does not exist ({} accessors)",
                        a.value(),
                        root.accessors.len()
                    ),
                ));
            }
        }
    }
    let mut errors = Vec::new();
    root.validate(root, gltf::json::Path::new, &mut |path, e| {
        let p = path();
        // Extensions this reader handles from the raw JSON: the crate does not know them.
        if e == VError::Unsupported
            && p.as_str().starts_with("extensionsRequired")
            && SUPPORTED_EXTENSIONS
                .iter()
                .any(|s| p.as_str().contains(&format!("\"{s}\"")))
        {
            return;
        }
        errors.push((p, e));
    });
    let Some((path, e)) = errors.into_iter().next() else {
        return Ok(());
    };
    let ptr = json_pointer(path.as_str());
    let value = raw.pointer(&ptr);
    let message = match e {
        VError::IndexOutOfBounds => match (value.and_then(|v| v.as_u64()), refers_to(&ptr)) {
            (Some(i), Some((one, many))) => {
                let n = raw.get(many).and_then(|v| v.as_array()).map_or(0, Vec::len);
                format!("{one} {i} does not exist ({n} {many})")
            }
            _ => format!(
                "index {} out of range",
                value.map_or("?".to_string(), |v| v.to_string())
            ),
        },
        VError::Missing if ptr.ends_with("/POSITION/min") || ptr.ends_with("/POSITION/max") => {
            "the POSITION accessor has no min or max (the specification requires both)".into()
        }
        VError::Missing => "required, missing".into(),
        VError::Invalid => format!(
            "invalid value {}",
            value.map_or("?".to_string(), |v| fastbrdf_io::shorten(
                &v.to_string(),
                60
            ))
        ),
        VError::Oversize => "too large".into(),
        VError::Unsupported => "unsupported".into(),
    };
    Err(ctx.err(&ptr, message))
}

/// `extensionsRequired` may only name extensions this reader handles (an error otherwise);
/// `extensionsUsed` that it does not read are named in a warning.
pub(super) fn check_extensions(
    ctx: &Ctx,
    raw: &serde_json::Value,
    warnings: &mut Vec<String>,
) -> Result<()> {
    let list = |key: &str| -> Vec<(usize, String)> {
        raw.get(key)
            .and_then(|v| v.as_array())
            .map(|a| {
                a.iter()
                    .enumerate()
                    .map(|(i, v)| (i, v.as_str().unwrap_or("?").to_string()))
                    .collect()
            })
            .unwrap_or_default()
    };
    for (i, ext) in list("extensionsRequired") {
        if !SUPPORTED_EXTENSIONS.contains(&ext.as_str()) {
            return Err(ctx.err(
                &format!("/extensionsRequired/{i}"),
                format!(
                    "'{}' is required and not supported (read: {})",
                    fastbrdf_io::shorten(&ext, 60),
                    SUPPORTED_EXTENSIONS.join(", ")
                ),
            ));
        }
    }
    let unused: Vec<String> = list("extensionsUsed")
        .into_iter()
        .map(|(_, e)| e)
        .filter(|e| !SUPPORTED_EXTENSIONS.contains(&e.as_str()))
        .collect();
    if !unused.is_empty() {
        warnings.push(format!(
            "extensions not rendered: {} (the scene is drawn without them)",
            unused.join(", ")
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paths_become_json_pointers() {
        assert_eq!(
            json_pointer("meshes[0].primitives[12].attributes[\"POSITION\"]"),
            "/meshes/0/primitives/12/attributes/POSITION"
        );
        assert_eq!(
            json_pointer("extensionsRequired[1] = \"KHR_x\""),
            "/extensionsRequired/1"
        );
        assert_eq!(json_pointer("asset.version"), "/asset/version");
        assert_eq!(json_pointer("a[\"b/c\"]"), "/a/b~1c");
        assert_eq!(
            refers_to("/meshes/0/primitives/0/attributes/POSITION"),
            Some(("accessor", "accessors"))
        );
        assert_eq!(refers_to("/nodes/3/children/0"), Some(("node", "nodes")));
        assert_eq!(refers_to("/nodes/3/mesh"), Some(("mesh", "meshes")));
    }
}
