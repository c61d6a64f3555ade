//! What every endpoint of the explorer's API shares: the answer, the query and the one place
//! it becomes model specs ([`spec_of`], [`chosen`]: parsed once per request), the reference,
//! and the request's limits.

use crate::CliError;
use crate::commands::view::state::{Measured, State};
use crate::commands::view::users::UserModel;
use crate::model_args::{self, Use};
use fastbrdf::ModelSpec;
use fastbrdf::kind::Shading;
use fastbrdf_gpu::user::GpuBrdf;
use serde_json::{Value, json};
use std::sync::Arc;

/// An HTTP answer: status, content type and body.
pub struct Response {
    pub status: u16,
    pub content_type: &'static str,
    pub body: Vec<u8>,
}

impl Response {
    pub fn json(v: &Value) -> Self {
        Self {
            status: 200,
            content_type: "application/json",
            body: serde_json::to_vec(v).expect("serialisable"),
        }
    }
    /// `{"error": message}` with `status`.
    pub fn error(status: u16, message: &str) -> Self {
        Self {
            status,
            content_type: "application/json",
            body: serde_json::to_vec(&json!({ "error": message })).expect("serialisable"),
        }
    }
}

impl From<CliError> for Response {
    fn from(e: CliError) -> Self {
        // Exit code 2 (bad input) is the client's fault; anything else is the server's.
        Response::error(
            if e.code == crate::EXIT_INPUT {
                400
            } else {
                500
            },
            &e.message,
        )
    }
}

/// Largest picture side the server renders, samples per pixel axis, and models per request:
/// a request cannot ask for more memory or time than these allow.
pub const MAX_SIZE: u32 = 1024;
pub const MAX_SPP: u32 = 4;
pub const MAX_MODELS: usize = 6;
/// Keys of the query that are not model parameters.
const RESERVED: [&str; 15] = [
    "models", "ref", "theta", "lang", "size", "spp", "mesh", "light", "client", "gen", "model",
    "quick", "flip", "env", "dfg",
];

/// The decoded query string, in order.
pub struct Query(pub Vec<(String, String)>);

impl Query {
    /// Parses `a=1&b=x%20y` (percent-decoding, `+` as space); malformed escapes are kept as
    /// they are (the value is then refused by whoever reads it).
    pub fn parse(q: &str) -> Self {
        Self(
            q.split('&')
                .filter(|s| !s.is_empty())
                .map(|kv| {
                    let (k, v) = kv.split_once('=').unwrap_or((kv, ""));
                    (decode(k), decode(v))
                })
                .collect(),
        )
    }
    pub fn get(&self, key: &str) -> Option<&str> {
        self.0
            .iter()
            .rev()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }
    pub fn need(&self, key: &str) -> Result<&str, CliError> {
        self.get(key)
            .ok_or_else(|| CliError::input(format!("missing query parameter '{key}'")))
    }
    /// The model parameters: every key that is not reserved, as `--param NAME=VALUE`.
    pub fn params(&self) -> Vec<(String, String)> {
        self.0
            .iter()
            .filter(|(k, _)| !RESERVED.contains(&k.as_str()))
            .cloned()
            .collect()
    }
}

/// Percent-decoding of one query component.
pub fn decode(s: &str) -> String {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'+' => out.push(b' '),
            b'%' if i + 2 < b.len() => {
                match u8::from_str_radix(std::str::from_utf8(&b[i + 1..i + 3]).unwrap_or("zz"), 16)
                {
                    Ok(x) => {
                        out.push(x);
                        i += 2;
                    }
                    Err(_) => out.push(b'%'),
                }
            }
            c => out.push(c),
        }
        i += 1;
    }
    String::from_utf8_lossy(&out).into_owned()
}

/// What the approximations are measured against: the one place that knows the kinds of
/// reference (`ref=` in every query).
pub enum Reference<'a> {
    /// A registry model, with the same parameters as the others.
    Model(&'static str),
    /// The server's `--measured` file (`ref=` its name).
    Measured(&'a Measured),
    /// A user's model (`--model file:PATH` or an upload; `ref=` its name), with the query's
    /// values.
    User(Arc<UserModel>),
}

impl<'a> Reference<'a> {
    pub fn from_query(q: &Query, state: &'a State) -> Result<Option<Self>, CliError> {
        match q.get("ref") {
            None | Some("") => Ok(None),
            Some(r) => match &state.measured {
                Some(m) if m.name == r => Ok(Some(Reference::Measured(m))),
                _ => match state.user(r) {
                    Some(u) => Ok(Some(Reference::User(u))),
                    None => Ok(Some(Reference::Model(checked_id(r)?))),
                },
            },
        }
    }
    /// What the page and the JSON call it: the model id, or the measured file's name.
    pub fn name(&self) -> &str {
        match self {
            Reference::Model(id) => id,
            Reference::Measured(m) => &m.name,
            Reference::User(u) => &u.name,
        }
    }
    /// The registry model, if the reference is one.
    pub fn model(&self) -> Option<&'static str> {
        match self {
            Reference::Model(id) => Some(id),
            Reference::Measured(_) | Reference::User(_) => None,
        }
    }
    /// What the JSON calls its kind: `model`, `measured` or `user`.
    pub fn kind(&self) -> &'static str {
        match self {
            Reference::Model(_) => "model",
            Reference::Measured(_) => "measured",
            Reference::User(_) => "user",
        }
    }
}

/// A registry id the explorer can show (something to shade with), with the registry's message
/// for an unknown one and the core's for a term that does not shade.
pub fn checked_id(id: &str) -> Result<&'static str, CliError> {
    let e = fastbrdf::registry::find(id)?;
    if e.info.kind.shading() == Shading::Not {
        ModelSpec::new(e.info.id, &[])?.shaded()?;
    }
    Ok(e.info.id)
}

/// One chosen model: a registry id or a user's model.
pub enum Pick {
    Registry(&'static str),
    User(Arc<UserModel>),
}

/// The chosen models (`models=a,b`: registry ids and the names of the users' models),
/// checked, at most [`MAX_MODELS`].
pub fn picks(q: &Query, state: &State) -> Result<Vec<Pick>, CliError> {
    let ids: Vec<&str> = q
        .need("models")?
        .split(',')
        .filter(|s| !s.is_empty())
        .collect();
    if ids.is_empty() || ids.len() > MAX_MODELS {
        return Err(CliError::input(format!(
            "models: give 1 to {MAX_MODELS} comma-separated model ids"
        )));
    }
    ids.into_iter()
        .map(|id| match state.user(id) {
            Some(u) => Ok(Pick::User(u)),
            None => checked_id(id).map(Pick::Registry),
        })
        .collect()
}

/// The spec of model `id` from the query's values, parsed once: those of `all` it takes (as
/// `fastbrdf compare` gives them), validated by the registry (its messages: out of range, not
/// a number, unknown choice; the model's own values first, so that a message names the model
/// chosen), as shading evaluates it.
pub fn spec_of(id: &str, all: &[(String, String)]) -> Result<ModelSpec, CliError> {
    model_args::spec(
        id,
        &model_args::own_pairs(id, all)?,
        None,
        None,
        Use::Shaded,
    )
}

/// Refuses a coloured `spec` (a value per colour channel, R,G,B) where one model is computed:
/// the plots, the albedo and the errors rows (a render and a shader take one). The core's
/// message quotes the value and its range; it names `id`, the model chosen, not the BRDF a
/// lobe or a distribution is shaded as (whose values, such as a distribution's `f0`, are
/// checked after the model's own).
pub fn one_model(id: &str, spec: &ModelSpec) -> Result<(), CliError> {
    // The model's own values first: their ranges are the model's.
    model_args::unshaded(id, spec)?.params()?;
    match spec.params() {
        Ok(_) => Ok(()),
        Err(fastbrdf::Error::InvalidParam {
            param,
            value,
            expected,
            ..
        }) => Err(fastbrdf::Error::InvalidParam {
            model: id.into(),
            param,
            value,
            expected,
        }
        .into()),
        Err(e) => Err(e.into()),
    }
}

/// Every parameter of the query must be taken by at least one chosen model.
pub fn check_unused(ids: &[&str], all: &[(String, String)]) -> Result<(), CliError> {
    for (k, _) in all {
        let mut used = false;
        for id in ids {
            used |= model_args::takes(id, k)?;
        }
        if !used {
            return Err(fastbrdf::Error::UnknownParam {
                model: ids.join(","),
                param: fastbrdf_io::shorten(k, 64),
            }
            .into());
        }
    }
    Ok(())
}

/// A user's model as a query chose it: compiled with the query's values of the parameters its
/// file declares.
pub struct UserPick {
    pub model: Arc<UserModel>,
    pub brdf: Arc<GpuBrdf>,
    /// The query's values it took.
    pub values: Vec<(String, String)>,
}

/// What a plots, albedo or render query chose: the registry models with their specs, parsed
/// once (a model reference first, each once; a measured or user's reference is not among
/// them), the users' models (a user's reference not among them: it is `ref_user`), and the
/// reference.
pub struct Chosen<'a> {
    pub models: Vec<(&'static str, ModelSpec)>,
    pub users: Vec<UserPick>,
    pub reference: Option<Reference<'a>>,
    /// The user's model that is the reference, compiled with the query's values.
    pub ref_user: Option<UserPick>,
}

/// The models of a plots, albedo or render query, a model reference first, each once, each
/// with its spec (a user's model: compiled with its values). A parameter goes to the registry
/// models that take it, and to the users' models whose file declares it; one that none takes
/// is refused.
pub fn chosen<'a>(state: &'a State, q: &Query) -> Result<Chosen<'a>, CliError> {
    let picks = picks(q, state)?;
    let reference = Reference::from_query(q, state)?;
    let all = q.params();
    let mut order: Vec<&'static str> = reference.iter().filter_map(Reference::model).collect();
    let ref_name = reference.as_ref().map(|r| r.name().to_string());
    let mut users: Vec<Arc<UserModel>> = vec![];
    for p in picks {
        match p {
            Pick::Registry(id) => {
                if !order.contains(&id) {
                    order.push(id);
                }
            }
            Pick::User(u) => {
                if ref_name.as_deref() != Some(&u.name) && !users.iter().any(|x| x.name == u.name) {
                    users.push(u);
                }
            }
        }
    }
    let ref_model = match &reference {
        Some(Reference::User(u)) => Some(u.clone()),
        _ => None,
    };
    let all_users: Vec<&Arc<UserModel>> = ref_model.iter().chain(users.iter()).collect();
    // The registry models get the values one of them takes or no user's model declares (the
    // latter then refused as unused, naming the value).
    let mut to_registry = Vec::new();
    for (k, v) in &all {
        let mut taken = false;
        for id in &order {
            taken |= model_args::takes(id, k)?;
        }
        if taken || !all_users.iter().any(|u| u.declares(k)) {
            to_registry.push((k.clone(), v.clone()));
        }
    }
    if order.is_empty() {
        if let Some((k, _)) = to_registry.first() {
            let names: Vec<&str> = all_users.iter().map(|u| u.name.as_str()).collect();
            return Err(fastbrdf::Error::UnknownParam {
                model: names.join(","),
                param: fastbrdf_io::shorten(k, 64),
            }
            .into());
        }
    } else {
        check_unused(&order, &to_registry)?;
    }
    let models = order
        .into_iter()
        .map(|id| Ok((id, spec_of(id, &to_registry)?)))
        .collect::<Result<_, CliError>>()?;
    let pick = |u: Arc<UserModel>| -> Result<UserPick, CliError> {
        let values: Vec<(String, String)> =
            all.iter().filter(|(k, _)| u.declares(k)).cloned().collect();
        Ok(UserPick {
            brdf: u.instance(&values)?,
            model: u,
            values,
        })
    };
    let ref_user = ref_model.map(pick).transpose()?;
    let users = users.into_iter().map(pick).collect::<Result<_, _>>()?;
    Ok(Chosen {
        models,
        users,
        reference,
        ref_user,
    })
}

/// The incidence angle `theta`, degrees in [0, 90) (default 30).
pub fn theta_i(q: &Query) -> Result<f64, CliError> {
    let t = q.get("theta").unwrap_or("30");
    let v: f64 = t.parse().map_err(|_| {
        CliError::input(format!(
            "theta '{}': not a number",
            fastbrdf_io::shorten(t, 64)
        ))
    })?;
    if !(0.0..90.0).contains(&v) {
        return Err(CliError::input(format!(
            "theta {v}: the incidence angle must be in [0, 90) degrees"
        )));
    }
    Ok(v)
}

/// Whole number `key` in `lo..=hi` (default `default`).
pub fn parse_u32(q: &Query, key: &str, default: u32, lo: u32, hi: u32) -> Result<u32, CliError> {
    let Some(t) = q.get(key) else {
        return Ok(default);
    };
    match t.parse::<u32>() {
        Ok(v) if (lo..=hi).contains(&v) => Ok(v),
        _ => Err(CliError::input(format!(
            "{key} '{}': must be a whole number from {lo} to {hi}",
            fastbrdf_io::shorten(t, 64)
        ))),
    }
}

/// Standard base64 (pictures inside JSON).
pub fn base64(bytes: &[u8]) -> String {
    const T: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::with_capacity(bytes.len().div_ceil(3) * 4);
    for c in bytes.chunks(3) {
        let n = (u32::from(c[0]) << 16)
            | (u32::from(*c.get(1).unwrap_or(&0)) << 8)
            | u32::from(*c.get(2).unwrap_or(&0));
        for (k, shift) in [18, 12, 6, 0].into_iter().enumerate() {
            if k <= c.len() {
                s.push(T[((n >> shift) & 63) as usize] as char);
            } else {
                s.push('=');
            }
        }
    }
    s
}
