//! The text formats: a BRDF Explorer `.brdf` file's blocks, the `// param` lines of a function
//! file, and parameter values as users type them.

use super::{Param, ParamKind, UserError};

/// A shader file split into its parameters and its code.
#[derive(Debug)]
pub(crate) struct Parsed {
    pub params: Vec<Param>,
    /// The code naga reads (a `.brdf` file's shader block; a function file whole).
    pub code: String,
    /// The user's file line of `code`'s first line, minus one.
    pub line_offset: usize,
}

/// A parameter's value.
#[derive(Clone, Debug, PartialEq)]
pub enum ParamValue {
    Float(f64),
    Bool(bool),
    Color([f32; 3]),
}

/// Splits a BRDF Explorer file the way the explorer reads it: lines outside `::begin NAME` /
/// `::end NAME` blocks (the `analytic` line, `#` comments) are ignored, as are blocks other
/// than `parameters` and `shader`; the `shader` block is the GLSL.
pub(crate) fn brdf_file(text: &str, origin: &str) -> Result<Parsed, UserError> {
    let err = |line: usize, m: String| UserError::input(format!("{origin}:{line}: {m}"));
    let mut block: Option<(String, usize)> = None;
    let mut params = Vec::new();
    // The shader block's text and the line of its `::begin shader`.
    let mut code: Option<(String, usize)> = None;
    let mut shader = String::new();
    for (k, raw) in text.lines().enumerate() {
        let line = k + 1;
        let t = raw.trim();
        if let Some(name) = t.strip_prefix("::begin") {
            if let Some((open, at)) = &block {
                return Err(err(
                    line,
                    format!("::begin inside the '{open}' block opened at line {at}"),
                ));
            }
            let name = name.trim().to_string();
            if name == "shader" && code.is_some() {
                return Err(err(line, "a second ::begin shader block".into()));
            }
            block = Some((name, line));
            continue;
        }
        if let Some(name) = t.strip_prefix("::end") {
            match &block {
                Some((open, at)) if open == name.trim() => {
                    if open == "shader" {
                        code = Some((std::mem::take(&mut shader), *at));
                    }
                    block = None;
                }
                Some((open, at)) => {
                    return Err(err(
                        line,
                        format!(
                            "'::end {}' closes the '{open}' block opened at line {at}",
                            name.trim()
                        ),
                    ));
                }
                None => return Err(err(line, "::end outside any ::begin block".into())),
            }
            continue;
        }
        match block.as_ref().map(|(n, _)| n.as_str()) {
            Some("parameters") if !t.is_empty() && !t.starts_with('#') => {
                params.push(brdf_param(t, line).map_err(|m| err(line, m))?);
            }
            Some("shader") => {
                shader.push_str(raw);
                shader.push('\n');
            }
            _ => {}
        }
    }
    if let Some((open, at)) = block {
        return Err(err(
            at,
            format!("::begin {open} is never ended (::end {open})"),
        ));
    }
    let (code, line_offset) = match code {
        // The code's first line is the one after `::begin shader`.
        Some((c, at)) => (c, at),
        _ => {
            return Err(UserError::input(format!(
                "{origin}: no ::begin shader / ::end shader block: a BRDF Explorer file's GLSL \
                 defines vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) there"
            )));
        }
    };
    check_names(&params, origin)?;
    Ok(Parsed {
        params,
        code,
        line_offset,
    })
}

/// One line of a `.brdf` parameters block.
fn brdf_param(t: &str, line: usize) -> Result<Param, String> {
    let w: Vec<&str> = t.split_whitespace().collect();
    declaration(&w, line).map_err(|m| format!("{m} (in '{t}')"))
}

/// `float NAME MIN MAX DEFAULT`, `bool NAME DEFAULT` or `color NAME R G B`.
fn declaration(w: &[&str], line: usize) -> Result<Param, String> {
    let num = |s: &str, what: &str| -> Result<f64, String> {
        let v: f64 = s
            .parse()
            .map_err(|_| format!("the {what} '{s}' is not a number"))?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(format!("the {what} '{s}' is not finite"))
        }
    };
    let kind = match (w.first().copied(), w.len()) {
        (Some("float"), 5) => {
            let (min, max, default) = (num(w[2], "min")?, num(w[3], "max")?, num(w[4], "default")?);
            if min > max {
                return Err(format!("min {min} is above max {max}"));
            }
            if default < min || default > max {
                return Err(format!("the default {default} is outside [{min}, {max}]"));
            }
            ParamKind::Float { min, max, default }
        }
        (Some("bool"), 3) => ParamKind::Bool {
            default: boolean(w[2])
                .ok_or_else(|| format!("the default '{}' is not 0 or 1", w[2]))?,
        },
        (Some("color"), 5) => ParamKind::Color {
            default: [
                num(w[2], "red")? as f32,
                num(w[3], "green")? as f32,
                num(w[4], "blue")? as f32,
            ],
        },
        (Some("float" | "bool" | "color"), _) => {
            return Err(
                "expected 'float NAME MIN MAX DEFAULT', 'bool NAME DEFAULT' or \
                 'color NAME R G B'"
                    .into(),
            );
        }
        _ => {
            return Err(format!(
                "unknown parameter type '{}': float, bool or color",
                w.first().unwrap_or(&"")
            ));
        }
    };
    Ok(Param {
        name: w[1].to_string(),
        kind,
        line,
    })
}

fn boolean(s: &str) -> Option<bool> {
    match s {
        "1" | "true" => Some(true),
        "0" | "false" => Some(false),
        _ => None,
    }
}

/// A function file: the whole text is code; `// param` lines declare the parameters
/// (`// param NAME MIN MAX DEFAULT` for a float, or `// param float|bool|color ...`).
pub(crate) fn function_file(text: &str, origin: &str) -> Result<Parsed, UserError> {
    let mut params = Vec::new();
    for (k, raw) in text.lines().enumerate() {
        let Some(rest) = raw.trim().strip_prefix("//") else {
            continue;
        };
        let mut w: Vec<&str> = rest.split_whitespace().collect();
        if w.first() != Some(&"param") {
            continue;
        }
        w.remove(0);
        if w.len() == 4 && !matches!(w[0], "float" | "bool" | "color") {
            w.insert(0, "float");
        }
        let p = declaration(&w, k + 1).map_err(|m| {
            UserError::input(format!("{origin}:{}: {m} (in '{}')", k + 1, raw.trim()))
        })?;
        params.push(p);
    }
    check_names(&params, origin)?;
    Ok(Parsed {
        params,
        code: text.to_string(),
        line_offset: 0,
    })
}

/// Parameter names are identifiers, distinct, and not the wrapper's (`fb_`, `gl_`).
fn check_names(params: &[Param], origin: &str) -> Result<(), UserError> {
    for (k, p) in params.iter().enumerate() {
        let n = &p.name;
        let ident = n
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
            && n.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
        let bad = if !ident {
            Some("is not an identifier (letters, digits, _)")
        } else if n.starts_with("fb_") || n.starts_with("fbu_") || n.starts_with("gl_") {
            Some("is reserved: names starting fb_, fbu_ or gl_ are the wrapper's")
        } else if n.contains("__") {
            Some("is reserved: names with a double underscore are GLSL's")
        } else if params[..k].iter().any(|q| q.name == *n) {
            Some("is declared twice")
        } else {
            None
        };
        if let Some(why) = bad {
            return Err(UserError::input(format!(
                "{origin}:{}: parameter '{n}' {why}",
                p.line
            )));
        }
    }
    Ok(())
}

/// The defaults of `params`, replaced by the `given` values (see `UserShader::values`).
pub(crate) fn values(
    params: &[Param],
    given: &[(String, String)],
    name: &str,
) -> Result<Vec<ParamValue>, UserError> {
    let mut out: Vec<ParamValue> = params
        .iter()
        .map(|p| match &p.kind {
            ParamKind::Float { default, .. } => ParamValue::Float(*default),
            ParamKind::Bool { default } => ParamValue::Bool(*default),
            ParamKind::Color { default } => ParamValue::Color(*default),
        })
        .collect();
    for (k, (key, text)) in given.iter().enumerate() {
        let Some(i) = params.iter().position(|p| p.name == *key) else {
            let known: Vec<&str> = params.iter().map(|p| p.name.as_str()).collect();
            let list = if known.is_empty() {
                "it has no parameters".to_string()
            } else {
                format!("its parameters: {}", known.join(", "))
            };
            return Err(UserError::input(format!(
                "{name} has no parameter '{key}'; {list}"
            )));
        };
        if given[..k].iter().any(|(q, _)| q == key) {
            return Err(UserError::input(format!(
                "parameter '{key}' of {name} is given twice"
            )));
        }
        let bad = |why: String| UserError::input(format!("parameter '{key}' of {name}: {why}"));
        let v = text.trim();
        out[i] = match &params[i].kind {
            ParamKind::Float { min, max, .. } => {
                let x: f64 = v
                    .parse()
                    .ok()
                    .filter(|x: &f64| x.is_finite())
                    .ok_or_else(|| bad(format!("'{v}' is not a finite number")))?;
                if x < *min || x > *max {
                    return Err(bad(format!("{v} is outside [{min}, {max}]")));
                }
                ParamValue::Float(x)
            }
            ParamKind::Bool { .. } => ParamValue::Bool(
                boolean(v).ok_or_else(|| bad(format!("'{v}' is not 0, 1, false or true")))?,
            ),
            ParamKind::Color { .. } => {
                let parts: Vec<&str> = v
                    .split(|c: char| c == ',' || c.is_whitespace())
                    .filter(|s| !s.is_empty())
                    .collect();
                let nums: Option<Vec<f32>> = parts
                    .iter()
                    .map(|s| s.parse::<f32>().ok().filter(|x| x.is_finite()))
                    .collect();
                match nums.as_deref() {
                    Some(&[g]) => ParamValue::Color([g; 3]),
                    Some(&[r, g, b]) => ParamValue::Color([r, g, b]),
                    _ => {
                        return Err(bad(format!(
                            "'{v}' is not a colour: three finite numbers 'r,g,b' or one grey"
                        )));
                    }
                }
            }
        };
    }
    Ok(out)
}

/// One `vec4<f32>` per value (floats and bools in x, colours in xyz), at least one.
pub(crate) fn param_block(values: &[ParamValue]) -> Vec<f32> {
    let mut out = vec![0.0f32; 4 * values.len().max(1)];
    for (k, v) in values.iter().enumerate() {
        match v {
            ParamValue::Float(x) => out[4 * k] = *x as f32,
            ParamValue::Bool(b) => out[4 * k] = f32::from(u8::from(*b)),
            ParamValue::Color(c) => out[4 * k..4 * k + 3].copy_from_slice(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const FILE: &str = "analytic\n# c\n::begin parameters\nfloat a 0 1 .5\nbool b 1\n\
                        color c 1 0.5 0\n::end parameters\n\n::begin shader\nvec3 BRDF(vec3 L, \
                        vec3 V, vec3 N, vec3 X, vec3 Y) { return vec3(a); }\n::end shader\n";

    #[test]
    fn a_brdf_file_splits_into_parameters_and_code() {
        let p = brdf_file(FILE, "x.brdf").unwrap();
        assert_eq!(p.params.len(), 3);
        assert_eq!(p.params[1].kind, ParamKind::Bool { default: true });
        assert_eq!(p.params[2].line, 6);
        assert!(p.code.starts_with("vec3 BRDF"), "{}", p.code);
        // The code's first line is line 10 of the file.
        assert_eq!(p.line_offset, 9);
    }

    #[test]
    fn malformed_brdf_files_name_the_line() {
        let e = brdf_file(&FILE.replace("float a 0 1 .5", "float a 0 1"), "x.brdf").unwrap_err();
        assert!(e.message.starts_with("x.brdf:4: expected"), "{e}");
        let e = brdf_file(&FILE.replace("bool b 1", "int b 1"), "x.brdf").unwrap_err();
        assert!(
            e.message.contains("x.brdf:5: unknown parameter type 'int'"),
            "{e}"
        );
        let e = brdf_file(&FILE.replace("::end shader", ""), "x.brdf").unwrap_err();
        assert!(
            e.message
                .contains("x.brdf:9: ::begin shader is never ended"),
            "{e}"
        );
        let e = brdf_file(&FILE.replace("float a 0 1 .5", "float a 0 1 2"), "x.brdf").unwrap_err();
        assert!(e.message.contains("default 2 is outside [0, 1]"), "{e}");
        let e = brdf_file(&FILE.replace("bool b", "bool a"), "x.brdf").unwrap_err();
        assert!(
            e.message
                .contains("x.brdf:5: parameter 'a' is declared twice"),
            "{e}"
        );
        let e = brdf_file("analytic\n", "x.brdf").unwrap_err();
        assert!(e.message.contains("no ::begin shader"), "{e}");
    }

    #[test]
    fn values_are_checked_against_the_declarations() {
        let p = brdf_file(FILE, "x.brdf").unwrap().params;
        let g = |k: &str, v: &str| vec![(k.to_string(), v.to_string())];
        let v = values(&p, &g("c", "0.1, 0.2 0.3"), "file:x.brdf").unwrap();
        assert_eq!(v[2], ParamValue::Color([0.1, 0.2, 0.3]));
        assert_eq!(v[0], ParamValue::Float(0.5));
        let e = values(&p, &g("a", "2"), "file:x.brdf").unwrap_err();
        assert_eq!(
            e.message,
            "parameter 'a' of file:x.brdf: 2 is outside [0, 1]"
        );
        let e = values(&p, &g("z", "2"), "file:x.brdf").unwrap_err();
        assert_eq!(
            e.message,
            "file:x.brdf has no parameter 'z'; its parameters: a, b, c"
        );
        assert!(values(&p, &g("b", "yes"), "file:x.brdf").is_err());
        assert!(values(&p, &g("a", "nan"), "file:x.brdf").is_err());
        let block = param_block(&values(&p, &g("b", "0"), "f").unwrap());
        assert_eq!(block, [0.5, 0., 0., 0., 0., 0., 0., 0., 1., 0.5, 0., 0.]);
    }

    #[test]
    fn function_files_declare_parameters_in_comments() {
        let t = "// a model\n// param alpha 0.01 1 0.2\n// param bool grey 1\nfn brdf() {}\n";
        let p = function_file(t, "m.wgsl").unwrap();
        assert_eq!(p.params[0].name, "alpha");
        assert_eq!(p.params[1].line, 3);
        let e = function_file("// param fb_x 0 1 0\n", "m.wgsl").unwrap_err();
        assert!(
            e.message
                .starts_with("m.wgsl:1: parameter 'fb_x' is reserved"),
            "{e}"
        );
    }
}
