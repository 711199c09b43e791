//! Who may talk to the preview. The `Host` a request names must be the
//! server itself (against DNS rebinding: a foreign page whose name resolves
//! to this machine sends its own name): the address served, `localhost`
//! for a loopback one, every address of the machine when listening on all
//! of them, and the names given with `--allow-host`. A POST must come from
//! the page itself, not from a page of another site (which a browser
//! tells by `Origin` and `Sec-Fetch-Site`).

use std::net::{IpAddr, SocketAddr};

/// The allowed `Host` values, lower-case, each with the port.
pub struct Guard {
    hosts: Vec<String>,
}

impl Guard {
    /// The guard of a server at `addr` (its real port) that also answers to
    /// the names `extra` (`name` or `name:port`).
    pub fn new(addr: SocketAddr, extra: &[String]) -> Guard {
        let port = addr.port();
        let mut ips = vec![addr.ip()];
        if addr.ip().is_unspecified() {
            // Unreadable interfaces leave the loopback names and `extra`.
            let own = if_addrs::get_if_addrs().unwrap_or_default();
            ips.extend(own.iter().map(|i| i.ip()));
        }
        let mut hosts: Vec<String> = ips
            .iter()
            .map(|&ip| SocketAddr::new(ip, port).to_string())
            .collect();
        if ips.iter().any(|ip| ip.is_loopback() || ip.is_unspecified()) {
            hosts.push(format!("localhost:{port}"));
            hosts.push(SocketAddr::new(IpAddr::from([127, 0, 0, 1]), port).to_string());
        }
        hosts.extend(extra.iter().map(|name| with_port(name.trim(), port)));
        if port == 80 {
            // Browsers leave the default port out of `Host`.
            let bare: Vec<String> = hosts
                .iter()
                .filter_map(|h| h.strip_suffix(":80").map(str::to_string))
                .collect();
            hosts.extend(bare);
        }
        for h in &mut hosts {
            h.make_ascii_lowercase();
        }
        hosts.sort();
        hosts.dedup();
        Guard { hosts }
    }

    /// Whether a request's `Host` header names this server.
    pub fn host_allowed(&self, host: Option<&str>) -> bool {
        host.is_some_and(|h| self.hosts.contains(&h.trim().to_ascii_lowercase()))
    }

    /// Whether a POST with these headers comes from the page served as
    /// `host` (already allowed), or from no browser page at all (a command
    /// line client sends neither header).
    pub fn post_allowed(host: &str, origin: Option<&str>, fetch_site: Option<&str>) -> bool {
        let site_ok = fetch_site.is_none_or(|s| {
            s.eq_ignore_ascii_case("same-origin") || s.eq_ignore_ascii_case("none")
        });
        let origin_ok = origin.is_none_or(|o| {
            o.trim()
                .eq_ignore_ascii_case(&format!("http://{}", host.trim()))
        });
        site_ok && origin_ok
    }
}

/// `name` as a `Host` value: kept when it has a port, else with `port`
/// (a bare IPv6 address gets its brackets).
fn with_port(name: &str, port: u16) -> String {
    let has_port = |rest: &str| {
        rest.rsplit_once(':')
            .is_some_and(|(_, p)| p.parse::<u16>().is_ok())
    };
    if let Some(rest) = name.strip_prefix('[') {
        if rest.contains("]:") && has_port(rest) {
            name.to_string()
        } else {
            format!("{name}:{port}")
        }
    } else if name.matches(':').count() > 1 {
        format!("[{name}]:{port}")
    } else if has_port(name) {
        name.to_string()
    } else {
        format!("{name}:{port}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_the_served_loopback_address_is_a_host() {
        let guard = Guard::new("127.0.0.1:8123".parse().expect("an address"), &[]);
        let ok = |h: &str| guard.host_allowed(Some(h));
        assert!(ok("127.0.0.1:8123"));
        assert!(ok("LOCALHOST:8123"));
        assert!(!ok("127.0.0.1:8124"));
        assert!(!ok("evil.example:8123"));
        assert!(!ok("127.0.0.1"));
        assert!(!guard.host_allowed(None));
        let lan = Guard::new("192.168.1.5:80".parse().expect("an address"), &[]);
        assert!(lan.host_allowed(Some("192.168.1.5")));
        assert!(lan.host_allowed(Some("192.168.1.5:80")));
        assert!(!lan.host_allowed(Some("localhost:80")));
    }

    #[test]
    fn all_addresses_and_allowed_names() {
        let extra = [
            "Studio.lan".to_string(),
            "proxy:9000".to_string(),
            "[fe80::1]".to_string(),
        ];
        let guard = Guard::new("0.0.0.0:8300".parse().expect("an address"), &extra);
        let ok = |h: &str| guard.host_allowed(Some(h));
        assert!(ok("localhost:8300") && ok("127.0.0.1:8300"));
        assert!(ok("studio.lan:8300") && ok("proxy:9000") && ok("[fe80::1]:8300"));
        assert!(!ok("studio.lan:9000") && !ok("evil.example:8300"));
        for own in if_addrs::get_if_addrs().unwrap_or_default() {
            assert!(ok(&SocketAddr::new(own.ip(), 8300).to_string()), "{own:?}");
        }
        let v6 = Guard::new("[::1]:8300".parse().expect("an address"), &[]);
        assert!(v6.host_allowed(Some("[::1]:8300")) && v6.host_allowed(Some("localhost:8300")));
    }

    #[test]
    fn posts_only_from_the_page() {
        let host = "127.0.0.1:8123";
        assert!(Guard::post_allowed(host, None, None));
        assert!(Guard::post_allowed(
            host,
            Some("http://127.0.0.1:8123"),
            Some("same-origin")
        ));
        assert!(!Guard::post_allowed(
            host,
            Some("http://evil.example"),
            None
        ));
        assert!(!Guard::post_allowed(host, Some("null"), None));
        assert!(!Guard::post_allowed(host, None, Some("cross-site")));
        assert!(!Guard::post_allowed(host, None, Some("same-site")));
        assert!(!Guard::post_allowed(
            host,
            Some("http://127.0.0.1:8123"),
            Some("cross-site")
        ));
    }
}
