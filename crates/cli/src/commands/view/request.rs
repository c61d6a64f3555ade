//! One request as the explorer answers it: the `Host` and cross-site checks, and [`handle`],
//! the one function that answers every request hyper parsed.

use super::api::{self, Query, Response};
use super::state::State;
use crate::CliError;
use std::net::{IpAddr, SocketAddr};

/// The page, embedded.
pub const PAGE: &str = concat!(
    include_str!("page/index.html"),
    "<script>\n\"use strict\";\n",
    include_str!("page/main.js"),
    include_str!("page/gpu.js"),
    include_str!("page/panes.js"),
    include_str!("page/kinds.js"),
    include_str!("page/user.js"),
    "task(start);\n</script>\n</body>\n</html>\n"
);

/// The one path that takes a request body: `POST /api/user`, a user's model to compile.
pub const UPLOAD: &str = "/api/user";

/// Longest request target (path and query) accepted.
pub const MAX_URL: usize = 8192;
/// One request as [`handle`] sees it.
pub struct Request<'a> {
    pub method: &'a str,
    /// The request target: path and query.
    pub target: &'a str,
    /// The authority the client asked for: the absolute-form target's, else the `Host` header
    /// (None: neither, as an HTTP/1.0 client may send).
    pub host: Option<&'a str>,
    /// Whether the request carries a body (a `Content-Length` above 0, or chunked).
    pub has_body: bool,
    /// The body, read by the server: only that of a `POST` to [`UPLOAD`] (at most
    /// [`api::MAX_UPLOAD`] bytes); None when unread.
    pub body: Option<&'a [u8]>,
    /// The `Sec-Fetch-Site` header (a browser's: `same-origin`, `same-site`, `cross-site`,
    /// `none`), if any.
    pub fetch_site: Option<&'a str>,
    /// The `Origin` header, if any.
    pub origin: Option<&'a str>,
}

/// Why a request for `/api/*` is refused as cross-site, or None. A page of another site can
/// make the browser send requests here (its `Host` is this server's), so refused are: a
/// request the browser marks `Sec-Fetch-Site: cross-site` or `same-site` (another port or
/// name of the same site), and one whose `Origin` is present and not `http://HOST[:PORT]` (or
/// `https://`, a proxy's) of an allowed host (`null` included). The page's own requests
/// (`same-origin`, a typed address: `none`) and clients that send neither header (curl) pass.
pub fn cross_site(hosts: &Hosts, req: &Request<'_>) -> Option<String> {
    if let Some(site) = req.fetch_site {
        let site = site.trim().to_ascii_lowercase();
        if site == "cross-site" || site == "same-site" {
            return Some(format!(
                "cross-site request refused (Sec-Fetch-Site: {}): the API answers the explorer's own page only",
                fastbrdf_io::shorten(&site, 32)
            ));
        }
    }
    if let Some(origin) = req.origin {
        let o = origin.trim();
        let authority = o
            .strip_prefix("http://")
            .or_else(|| o.strip_prefix("https://"));
        if !authority.is_some_and(|a| !a.is_empty() && !a.contains('/') && hosts.allows(a)) {
            return Some(format!(
                "cross-site request refused (Origin '{}' is not this server, {}): the API answers the explorer's own page only",
                fastbrdf_io::shorten(origin, 64),
                hosts.expected()
            ));
        }
    }
    None
}

/// The names the server answers to (`Host`): the bound address with the bound port; on a
/// loopback address also `localhost`, `127.0.0.1` and `[::1]`; on an unspecified address
/// (`0.0.0.0`, `::`) any IP literal and `localhost`; and each `--allow-host` (`NAME`: any
/// port, `NAME:PORT`: that one). A page served under another name that resolves to this
/// machine (DNS rebinding) gets 403 instead of the API.
pub struct Hosts {
    ip: IpAddr,
    port: u16,
    extra: Vec<String>,
}

impl Hosts {
    pub fn new(bound: SocketAddr, extra: &[String]) -> Self {
        Self {
            ip: bound.ip(),
            port: bound.port(),
            extra: extra
                .iter()
                .map(|e| e.trim().to_ascii_lowercase())
                .collect(),
        }
    }

    /// Splits `name[:port]` (`[v6]:port` for IPv6); None when the port is not a number.
    fn split(host: &str) -> Option<(&str, Option<u16>)> {
        let (name, port) = if let Some(rest) = host.strip_prefix('[') {
            let (name, after) = rest.split_once(']')?;
            match after {
                "" => (name, None),
                _ => (name, Some(after.strip_prefix(':')?)),
            }
        } else {
            match host.rsplit_once(':') {
                Some((n, p)) if !n.contains(':') => (n, Some(p)),
                _ => (host, None),
            }
        };
        let port = match port {
            Some(p) => Some(p.parse().ok()?),
            None => None,
        };
        Some((name, port))
    }

    /// Whether a request for `host` is answered.
    pub fn allows(&self, host: &str) -> bool {
        let host = host.trim().to_ascii_lowercase();
        let Some((name, port)) = Self::split(&host) else {
            return false;
        };
        let name = name.strip_suffix('.').unwrap_or(name);
        for e in &self.extra {
            match Self::split(e) {
                Some((n, None)) if n == name => return true,
                Some((n, Some(p))) if n == name && Some(p) == port => return true,
                _ => {}
            }
        }
        if port.unwrap_or(80) != self.port {
            return false;
        }
        let local = self.ip.is_loopback() || self.ip.is_unspecified();
        match name.parse::<IpAddr>() {
            Ok(ip) => {
                ip == self.ip
                    || self.ip.is_unspecified()
                    || (self.ip.is_loopback() && ip.is_loopback())
            }
            Err(_) => local && name == "localhost",
        }
    }

    /// What the bound address is called in messages.
    fn expected(&self) -> String {
        SocketAddr::new(self.ip, self.port).to_string()
    }
}

/// Answers one request: the one place that does, for every request hyper parsed (the
/// transport only adds refusals before a request exists: the connection cap's 503, hyper's
/// 400/431 for a malformed or oversized head, the HTTP/2 preface's GOAWAY). Never panics: a
/// handler's panic is a 500.
pub fn handle(state: &State, hosts: &Hosts, req: &Request<'_>) -> Response {
    if let Some(host) = req.host
        && !hosts.allows(host)
    {
        return Response::error(
            403,
            &format!(
                "Host '{}' is not this server's address ({}); requests for other names are refused (DNS rebinding). Add --allow-host NAME to serve under another name (a reverse proxy)",
                fastbrdf_io::shorten(host, 64),
                hosts.expected()
            ),
        );
    }
    if req.target.starts_with("/api/")
        && let Some(why) = cross_site(hosts, req)
    {
        return Response::error(403, &why);
    }
    let (method, target) = (req.method, req.target);
    let (path, query) = target.split_once('?').unwrap_or((target, ""));
    let upload = method == "POST" && path == UPLOAD;
    if target.len() > MAX_URL {
        return Response::error(414, &format!("request target longer than {MAX_URL} bytes"));
    }
    if req.has_body && !(upload && req.body.is_some()) {
        return Response::error(
            413,
            "request bodies are refused: the API is GET-only (but POST /api/user, a user's model), parameters go in the query",
        );
    }
    if path == UPLOAD && !upload {
        return Response::error(
            405,
            &format!(
                "method {} {UPLOAD}: only POST, with the file as the body and ?name=FILE.brdf|.wgsl|.glsl",
                fastbrdf_io::shorten(method, 16)
            ),
        );
    }
    if method != "GET" && !upload {
        return Response::error(
            405,
            &format!("method {}: only GET", fastbrdf_io::shorten(method, 16)),
        );
    }
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        let q = Query::parse(query);
        let r: Result<Response, CliError> = match path {
            "/" | "/index.html" => Ok(Response {
                status: 200,
                content_type: "text/html; charset=utf-8",
                body: PAGE.as_bytes().to_vec(),
            }),
            // No icon: an empty answer instead of a 404 (a console error on every page load).
            "/favicon.ico" => Ok(Response {
                status: 204,
                content_type: "image/x-icon",
                body: Vec::new(),
            }),
            "/api/models" => Ok(api::models(state)),
            "/api/plots" => api::plots(state, &q),
            "/api/panes" => api::panes(state, &q),
            "/api/albedo" => api::albedo_endpoint(state, &q),
            "/api/render" => api::render_endpoint(state, &q),
            "/api/gpu/scene" => api::gpu_scene(state, &q),
            "/api/gpu/shader" => api::gpu_shader(state, &q),
            "/api/flip" => api::flip_endpoint(state, &q),
            "/api/errors" => api::errors_endpoint(state, &q),
            "/api/shader" => api::shader(state, &q),
            "/api/material" => api::material(&q),
            UPLOAD => api::upload(state, &q, req.body.unwrap_or_default()),
            "/api/conform" => api::conform_endpoint(state, &q),
            // Nothing else exists: no file is ever read from a path, so `..` leads nowhere.
            _ => Ok(Response::error(
                404,
                &format!("no such page: {}", fastbrdf_io::shorten(path, 64)),
            )),
        };
        r.unwrap_or_else(Response::from)
    }));
    result.unwrap_or_else(|_| Response::error(500, "internal error (a panic); the server goes on"))
}

/// `--allow-host`'s value: a host name or address, optionally with `:PORT`.
pub fn host_name(s: &str) -> Result<String, String> {
    let ok = !s.is_empty()
        && s.len() <= 253
        && s.bytes()
            .all(|b| b.is_ascii_alphanumeric() || b"-._:[]".contains(&b))
        && Hosts::split(&s.to_ascii_lowercase()).is_some();
    if ok {
        Ok(s.to_string())
    } else {
        Err(format!(
            "'{}' is not a host name (letters, digits, '-', '.', an optional ':PORT')",
            fastbrdf_io::shorten(s, 64)
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hosts_name_the_bound_address_only() {
        let loopback = Hosts::new("127.0.0.1:8000".parse().unwrap(), &[]);
        for ok in [
            "127.0.0.1:8000",
            "localhost:8000",
            "LocalHost.:8000",
            "[::1]:8000",
            "127.0.0.2:8000",
        ] {
            assert!(loopback.allows(ok), "{ok}");
        }
        for bad in [
            "evil.example:8000",
            "localhost",
            "localhost:8001",
            "127.0.0.1",
            "10.0.0.1:8000",
            "[::1]",
            "[::1:8000",
            "localhost:80x",
            "",
        ] {
            assert!(!loopback.allows(bad), "{bad}");
        }
        let on_80 = Hosts::new("[::1]:80".parse().unwrap(), &["proxy.example:443".into()]);
        assert!(on_80.allows("localhost") && on_80.allows("[::1]"));
        assert!(on_80.allows("proxy.example:443") && !on_80.allows("proxy.example"));
        let any = Hosts::new("0.0.0.0:9000".parse().unwrap(), &["box.lan".into()]);
        assert!(any.allows("192.168.1.7:9000") && any.allows("localhost:9000"));
        assert!(any.allows("box.lan") && any.allows("box.lan:1234"));
        assert!(!any.allows("evil.example:9000") && !any.allows("192.168.1.7:9001"));
        let lan = Hosts::new("192.168.1.7:9000".parse().unwrap(), &[]);
        assert!(lan.allows("192.168.1.7:9000"));
        assert!(!lan.allows("localhost:9000") && !lan.allows("127.0.0.1:9000"));
    }
}
