//! The user's code inside fastbrdf's wrapper, through naga: compile errors mapped back to the
//! user's file, line and column; the checked module renamed (`fbu_`) and written as WGSL.
//!
//! GLSL (a `.brdf` shader block, a `.glsl` file) gets two lines in front: `#version 450`
//! (naga's GLSL front end reads 440 to 460; BRDF Explorer's templates say 410, whose implicit
//! int-to-float conversions naga accepts as well) and, on one line, the parameter buffer and
//! one global per parameter (bools are `bool` globals set from a float: uniform buffers hold
//! no bools). WGSL gets the same declarations after the user's code (module scope is
//! order-free), so its lines are the user's own. After the code come the `fb_user_*`
//! functions and, for GLSL, the empty `main` naga's front end requires (dropped afterwards).

use super::parse::Parsed;
use super::{Language, ParamKind, UserError};
use naga::{Scalar, TypeInner, VectorSize};

/// The checked module and what it offers.
pub(crate) struct Translated {
    pub module: naga::Module,
    pub channels: usize,
    pub samples: bool,
    pub own_weight: bool,
}

/// Where the user's code sits in the text naga reads.
struct Layout<'a> {
    origin: &'a str,
    text: String,
    /// Lines of wrapper before the user's first line.
    before: usize,
    /// Lines of user code.
    lines: usize,
    /// The user's file line of the code's first line, minus one.
    offset: usize,
}

impl Layout<'_> {
    /// `origin:line:col: error: message` for a span of `self.text`.
    fn at(&self, span: naga::Span, message: &str) -> String {
        let origin = self.origin;
        let Some(range) = span.to_range() else {
            return format!("{origin}: error: {message}");
        };
        let start = range.start.min(self.text.len());
        let head = self.text.get(..start).unwrap_or("");
        let line = head.matches('\n').count() + 1;
        let col = head.rsplit('\n').next().unwrap_or("").chars().count() + 1;
        if line > self.before && line <= self.before + self.lines {
            let l = line - self.before + self.offset;
            format!("{origin}:{l}:{col}: error: {message}")
        } else {
            let code = self.text.lines().nth(line - 1).unwrap_or("").trim();
            let code: String = code.chars().take(160).collect();
            format!(
                "{origin}: error: {message} (in the code fastbrdf adds around the shader, which \
                 declares the parameters and calls the shader's functions: '{code}')"
            )
        }
    }
}

/// The function names a shader may define, per language.
struct Names {
    brdf: &'static str,
}

/// Parses, checks and wraps the user's code.
pub(crate) fn translate(p: &Parsed, origin: &str, lang: Language) -> Result<Translated, UserError> {
    let names = Names {
        brdf: if lang == Language::Brdf {
            "BRDF"
        } else {
            "brdf"
        },
    };
    // Pass 1: the user's code with the parameter declarations, to see what it defines.
    let first = layout(p, origin, lang, None);
    let m = front(&first, lang)?;
    no_bindings(&m, &first)?;
    let found = inspect(&m, p, origin, lang, &names)?;
    // Pass 2: with the wrapper functions, checked.
    let full = layout(p, origin, lang, Some(&found));
    let mut module = front(&full, lang)?;
    module.entry_points.clear();
    validator()
        .validate(&module)
        .map_err(|e| UserError::input(validation_message(&full, &e)))?;
    rename(&mut module);
    Ok(Translated {
        module,
        channels: found.channels,
        samples: found.samples,
        own_weight: found.own_weight,
    })
}

/// What the user's code defines.
struct Found {
    channels: usize,
    samples: bool,
    own_weight: bool,
}

fn validator() -> naga::valid::Validator {
    naga::valid::Validator::new(
        naga::valid::ValidationFlags::all(),
        naga::valid::Capabilities::default(),
    )
}

/// The text naga reads: declarations, the user's code and (with `found`) the wrapper.
fn layout<'a>(p: &Parsed, origin: &'a str, lang: Language, found: Option<&Found>) -> Layout<'a> {
    let k = p.params.len().max(1);
    let lines = p.code.lines().count();
    let glsl = lang != Language::Wgsl;
    let mut decl = String::new();
    let mut load = String::new();
    for (i, q) in p.params.iter().enumerate() {
        let n = &q.name;
        let (ty, get) = match (&q.kind, glsl) {
            (ParamKind::Float { .. }, true) => ("float", format!("fb_user_params.p[{i}].x")),
            (ParamKind::Bool { .. }, true) => ("bool", format!("fb_user_params.p[{i}].x != 0.0")),
            (ParamKind::Color { .. }, true) => ("vec3", format!("fb_user_params.p[{i}].xyz")),
            (ParamKind::Float { .. }, false) => ("f32", format!("fb_user_params.p[{i}].x")),
            (ParamKind::Bool { .. }, false) => ("bool", format!("fb_user_params.p[{i}].x != 0.0")),
            (ParamKind::Color { .. }, false) => ("vec3<f32>", format!("fb_user_params.p[{i}].xyz")),
        };
        if glsl {
            decl.push_str(&format!(" {ty} {n};"));
        } else {
            decl.push_str(&format!("var<private> {n}: {ty};\n"));
        }
        load.push_str(&format!(" {n} = {get};"));
    }
    let brdf = if lang == Language::Brdf {
        "BRDF"
    } else {
        "brdf"
    };
    let mut text = String::new();
    let before;
    if glsl {
        text.push_str("#version 450\n");
        text.push_str(&format!(
            "layout(std140, set = 1, binding = 0) uniform FbUserParams {{ vec4 p[{k}]; }} \
             fb_user_params;{decl}\n"
        ));
        before = 2;
        // naga takes one `#version`, first: the user's is blanked (the line stays).
        for l in p.code.lines() {
            if !l.trim_start().starts_with("#version") {
                text.push_str(l);
            }
            text.push('\n');
        }
        if let Some(f) = found {
            text.push_str(&format!("void fb_user_load() {{{load} }}\n"));
            let call = if lang == Language::Brdf {
                "BRDF(wi, wo, vec3(0.0, 0.0, 1.0), vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0))"
            } else {
                "vec3(brdf(wi, wo))"
            };
            text.push_str(&format!(
                "vec3 fb_user_brdf(vec3 wi, vec3 wo) {{ fb_user_load(); return {call}; }}\n"
            ));
            if f.samples {
                text.push_str(
                    "vec4 fb_user_sample(vec3 wo, vec2 u) { fb_user_load(); return \
                     brdf_sample(wo, u); }\n\
                     float fb_user_pdf(vec3 wo, vec3 wi) { fb_user_load(); return \
                     brdf_pdf(wo, wi); }\n",
                );
                let w = if f.own_weight {
                    "vec3(brdf_weight(wo, wi, pdf))"
                } else {
                    "vec3(brdf(wi, wo)) * max(wi.z, 0.0) / pdf"
                };
                text.push_str(&format!(
                    "vec3 fb_user_weight(vec3 wo, vec3 wi, float pdf) {{ fb_user_load(); \
                     return {w}; }}\n"
                ));
            }
        }
        text.push_str("layout(local_size_x = 1) in;\nvoid main() {}\n");
    } else {
        before = 0;
        text.push_str(&p.code);
        if !p.code.ends_with('\n') {
            text.push('\n');
        }
        text.push_str(&format!(
            "struct FbUserParams {{ p: array<vec4<f32>, {k}>, }}\n\
             @group(1) @binding(0) var<uniform> fb_user_params: FbUserParams;\n{decl}"
        ));
        if let Some(f) = found {
            text.push_str(&format!("fn fb_user_load() {{{load} }}\n"));
            text.push_str(&format!(
                "fn fb_user_brdf(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {{ fb_user_load(); \
                 return vec3<f32>({brdf}(wi, wo)); }}\n"
            ));
            if f.samples {
                text.push_str(
                    "fn fb_user_sample(wo: vec3<f32>, u: vec2<f32>) -> vec4<f32> { \
                     fb_user_load(); return brdf_sample(wo, u); }\n\
                     fn fb_user_pdf(wo: vec3<f32>, wi: vec3<f32>) -> f32 { fb_user_load(); \
                     return brdf_pdf(wo, wi); }\n",
                );
                let w = if f.own_weight {
                    "vec3<f32>(brdf_weight(wo, wi, pdf))"
                } else {
                    "vec3<f32>(brdf(wi, wo)) * max(wi.z, 0.0) / pdf"
                };
                text.push_str(&format!(
                    "fn fb_user_weight(wo: vec3<f32>, wi: vec3<f32>, pdf: f32) -> vec3<f32> {{ \
                     fb_user_load(); return {w}; }}\n"
                ));
            }
        }
    }
    Layout {
        origin,
        text,
        before,
        lines,
        offset: p.line_offset,
    }
}

/// naga's front end for `lang` over `l.text`, errors in the user's coordinates.
fn front(l: &Layout, lang: Language) -> Result<naga::Module, UserError> {
    if lang == Language::Wgsl {
        naga::front::wgsl::parse_str(&l.text).map_err(|e| {
            let mut msg = e.message().to_string();
            let span = e.labels().next().map(|(s, label)| {
                if !label.is_empty() && !msg.contains(label) {
                    msg = format!("{msg} ({label})");
                }
                s
            });
            UserError::input(l.at(span.unwrap_or_default(), &msg))
        })
    } else {
        let mut fe = naga::front::glsl::Frontend::default();
        let opts = naga::front::glsl::Options::from(naga::ShaderStage::Compute);
        fe.parse(&opts, &l.text).map_err(|e| {
            let msgs: Vec<String> = e
                .errors
                .iter()
                .take(5)
                .map(|x| l.at(x.meta, &x.kind.to_string()))
                .collect();
            UserError::input(msgs.join("\n"))
        })
    }
}

/// A validation error with its causes, at its innermost span.
fn validation_message(l: &Layout, e: &naga::WithSpan<naga::valid::ValidationError>) -> String {
    let mut msg = e.as_inner().to_string();
    let mut src = std::error::Error::source(e.as_inner());
    while let Some(s) = src {
        msg.push_str(": ");
        msg.push_str(&s.to_string());
        src = s.source();
    }
    let span = e
        .spans()
        .filter(|(s, _)| s.to_range().is_some())
        .last()
        .map(|(s, _)| *s)
        .unwrap_or_default();
    l.at(span, &msg)
}

/// A user shader reads its parameters only: a resource of its own (a uniform, a buffer, a
/// texture) would have nothing bound to it.
fn no_bindings(m: &naga::Module, l: &Layout) -> Result<(), UserError> {
    for (h, g) in m.global_variables.iter() {
        let name = g.name.as_deref().unwrap_or("");
        if g.binding.is_some() && name != "fb_user_params" {
            let msg = format!(
                "'{name}' is a resource (a uniform, buffer, texture or sampler), which nothing \
                 would bind: a shader's inputs are its directions and its declared parameters"
            );
            return Err(UserError::input(l.at(m.global_variables.get_span(h), &msg)));
        }
    }
    Ok(())
}

/// The user's functions: the BRDF's signature decides the channels; `brdf_sample` and
/// `brdf_pdf` come together; `brdf_weight` needs them.
fn inspect(
    m: &naga::Module,
    p: &Parsed,
    origin: &str,
    lang: Language,
    names: &Names,
) -> Result<Found, UserError> {
    let glsl = lang != Language::Wgsl;
    let f32_ = TypeInner::Scalar(Scalar::F32);
    let vec = |n| TypeInner::Vector {
        size: n,
        scalar: Scalar::F32,
    };
    let func = |name: &str| {
        m.functions
            .iter()
            .map(|(_, f)| f)
            .find(|f| f.name.as_deref() == Some(name))
    };
    let sig = |f: &naga::Function| -> (Vec<TypeInner>, Option<TypeInner>) {
        (
            f.arguments
                .iter()
                .map(|a| m.types[a.ty].inner.clone())
                .collect(),
            f.result.as_ref().map(|r| m.types[r.ty].inner.clone()),
        )
    };
    // Where the user wrote `name(`, for messages about a function.
    let place = |name: &str| -> String {
        let needle = format!("{name}(");
        for (k, line) in p.code.lines().enumerate() {
            let mut from = 0;
            while let Some(i) = line[from..].find(&needle) {
                let at = from + i;
                let before = line[..at].chars().next_back();
                if !before.is_some_and(|c| c.is_alphanumeric() || c == '_') {
                    let col = line[..at].chars().count() + 1;
                    return format!("{origin}:{}:{col}", k + 1 + p.line_offset);
                }
                from = at + 1;
            }
        }
        origin.to_string()
    };
    let spell = |args: &str, ret: &str| -> String {
        if glsl {
            format!("{ret} {{}}({args})")
        } else {
            format!("fn {{}}({args}) -> {ret}")
        }
    };
    let v3 = if glsl { "vec3" } else { "vec3<f32>" };
    let fl = if glsl { "float" } else { "f32" };
    let brdf = names.brdf;
    let channels = if lang == Language::Brdf {
        let want = "vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)";
        let Some(f) = func(brdf) else {
            return Err(UserError::input(format!(
                "{origin}: error: the shader block defines no function {want}"
            )));
        };
        if sig(f) != (vec![vec(VectorSize::Tri); 5], Some(vec(VectorSize::Tri))) {
            return Err(UserError::input(format!(
                "{}: error: BRDF must be {want}",
                place(brdf)
            )));
        }
        3
    } else {
        let args = if glsl {
            "vec3 wi, vec3 wo"
        } else {
            "wi: vec3<f32>, wo: vec3<f32>"
        };
        let want = format!(
            "{} or {}",
            spell(args, fl).replace("{}", brdf),
            spell(args, v3).replace("{}", brdf)
        );
        let Some(f) = func(brdf) else {
            return Err(UserError::input(format!(
                "{origin}: error: the shader defines no function {want}"
            )));
        };
        let (a, r) = sig(f);
        match (a == vec![vec(VectorSize::Tri); 2], r) {
            (true, Some(t)) if t == f32_ => 1,
            (true, Some(t)) if t == vec(VectorSize::Tri) => 3,
            _ => {
                return Err(UserError::input(format!(
                    "{}: error: brdf must be {want}",
                    place(brdf)
                )));
            }
        }
    };
    let check = |name: &str, args: Vec<TypeInner>, ret: TypeInner, text: String| match func(name) {
        None => Ok(false),
        Some(f) if sig(f) == (args, Some(ret)) => Ok(true),
        Some(_) => Err(UserError::input(format!(
            "{}: error: {name} must be {}",
            place(name),
            text.replace("{}", name)
        ))),
    };
    let (s_args, p_args, w_args) = if glsl {
        (
            "vec3 wo, vec2 u",
            "vec3 wo, vec3 wi",
            "vec3 wo, vec3 wi, float pdf",
        )
    } else {
        (
            "wo: vec3<f32>, u: vec2<f32>",
            "wo: vec3<f32>, wi: vec3<f32>",
            "wo: vec3<f32>, wi: vec3<f32>, pdf: f32",
        )
    };
    let ret = if channels == 1 {
        f32_.clone()
    } else {
        vec(VectorSize::Tri)
    };
    let ret_name = if channels == 1 { fl } else { v3 };
    let sample = check(
        "brdf_sample",
        vec![vec(VectorSize::Tri), vec(VectorSize::Bi)],
        vec(VectorSize::Quad),
        spell(s_args, if glsl { "vec4" } else { "vec4<f32>" }),
    )?;
    let pdf = check(
        "brdf_pdf",
        vec![vec(VectorSize::Tri); 2],
        f32_.clone(),
        spell(p_args, fl),
    )?;
    let weight = check(
        "brdf_weight",
        vec![vec(VectorSize::Tri), vec(VectorSize::Tri), f32_],
        ret,
        spell(w_args, ret_name),
    )?;
    if lang == Language::Brdf && (sample || pdf || weight) {
        // BRDF Explorer files do not sample; names that happen to match are helpers.
        return Ok(Found {
            channels,
            samples: false,
            own_weight: false,
        });
    }
    if sample != pdf {
        let (has, lacks) = if sample {
            ("brdf_sample", "brdf_pdf")
        } else {
            ("brdf_pdf", "brdf_sample")
        };
        return Err(UserError::input(format!(
            "{}: error: the shader defines {has} but not {lacks}: a sampler needs both",
            place(has)
        )));
    }
    if weight && !sample {
        return Err(UserError::input(format!(
            "{}: error: brdf_weight without brdf_sample and brdf_pdf",
            place("brdf_weight")
        )));
    }
    Ok(Found {
        channels,
        samples: sample,
        own_weight: weight,
    })
}

/// Prefixes every module-scope name but the wrapper's with `fbu_`.
fn rename(m: &mut naga::Module) {
    let fix = |n: &mut Option<String>| {
        if let Some(s) = n
            && !s.starts_with("fb_user_")
            && s != "FbUserParams"
        {
            *s = format!("fbu_{s}");
        }
    };
    for (_, f) in m.functions.iter_mut() {
        fix(&mut f.name);
    }
    for (_, g) in m.global_variables.iter_mut() {
        fix(&mut g.name);
    }
    for (_, c) in m.constants.iter_mut() {
        fix(&mut c.name);
    }
    for (_, o) in m.overrides.iter_mut() {
        fix(&mut o.name);
    }
    // Types live in a unique arena: rebuilt in order, so every handle stays.
    let old = std::mem::take(&mut m.types);
    for (h, t) in old.iter() {
        let mut t = t.clone();
        fix(&mut t.name);
        let n = m.types.insert(t, old.get_span(h));
        debug_assert_eq!(n, h);
    }
}

/// The module as WGSL with its parameter buffer at `group`, `binding`.
pub(crate) fn write_wgsl(
    module: &naga::Module,
    group: u32,
    binding: u32,
) -> Result<String, String> {
    let mut m = module.clone();
    for (_, g) in m.global_variables.iter_mut() {
        if g.name.as_deref() == Some("fb_user_params") {
            g.binding = Some(naga::ResourceBinding { group, binding });
        }
    }
    let info = validator()
        .validate(&m)
        .map_err(|e| format!("the translated shader does not validate: {e}"))?;
    naga::back::wgsl::write_string(&m, &info, naga::back::wgsl::WriterFlags::empty())
        .map_err(|e| format!("writing WGSL failed: {e}"))
}
