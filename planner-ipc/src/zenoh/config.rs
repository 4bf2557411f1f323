//! Session configuration: the settings the planner service over Zenoh depends on, applied
//! on top of an optional Zenoh configuration file.
//!
//! Each process opens up to two sessions (see the [module documentation](super)):
//!
//! - the **plan session** (plan queries, planner info, liveliness): the low-latency unicast
//!   transport (`transport/unicast/lowlatency: true`, `transport/unicast/qos/enabled: false`;
//!   both ends must agree, or the handshake fails). It cannot fragment: no message may
//!   exceed 65,535 bytes, so long answers travel in parts ([`super::MAX_PART`]);
//! - the **map session** (map publication and the latest-version queryable): Zenoh's default
//!   transport, which fragments, drops for a congested receiver instead of blocking the
//!   sender ([`CongestionControl::Drop`](::zenoh::qos::CongestionControl)), and rejects
//!   messages over its receivers' `transport/link/rx/max_message_size`. It uses its own
//!   endpoints: by default every plan endpoint with the next port (`tcp/H:7447` ->
//!   `tcp/H:7448`).
//!
//! Both: multicast scouting off (peers meet only through the endpoints given, and gossip),
//! and a quick reconnection schedule (100 ms, doubling up to 1 s) so that a restarted router
//! is found again within about a second.
//!
//! The Zenoh runtime's threads are configured per process, only through the `ZENOH_RUNTIME`
//! environment variable, read once when the runtime starts: [`ONE_WORKER_RUNTIME`] hands
//! every runtime over to one worker, which together with the low-latency transport halves
//! the round trip (see `docs/zenoh.md`). The binaries set it at the start of `main` when it
//! is unset ([`runtime_env_is_one_worker`] says whether it is in effect).

use std::fmt;
use std::path::PathBuf;

/// How a session takes part in the Zenoh network.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Connects to the endpoints given and to peers it learns of (gossip); accepts peers.
    Peer,
    /// Connects to one router or peer of the endpoints given, routes nothing.
    Client,
    /// Routes for clients and peers (a router of our own: no `zenohd` needed).
    Router,
}

impl Mode {
    /// Zenoh's name of the mode.
    pub fn as_str(self) -> &'static str {
        match self {
            Mode::Peer => "peer",
            Mode::Client => "client",
            Mode::Router => "router",
        }
    }
}

/// Which of a process's two sessions a configuration is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SessionKind {
    /// Plans, planner info, liveliness: the low-latency transport.
    Plan,
    /// Maps: the default transport (fragmenting, congestion control).
    Map,
}

/// Where and how to reach the Zenoh network.
#[derive(Clone, Debug)]
pub struct ZenohOptions {
    /// The mode of both sessions.
    pub mode: Mode,
    /// Endpoints the plan session listens on (`tcp/127.0.0.1:7447`); none for a client.
    pub listen: Vec<String>,
    /// Endpoints the plan session connects to.
    pub connect: Vec<String>,
    /// Endpoints the map session listens on; `None`: [`listen`](Self::listen) with the next
    /// port.
    pub map_listen: Option<Vec<String>>,
    /// Endpoints the map session connects to; `None`: [`connect`](Self::connect) with the
    /// next port.
    pub map_connect: Option<Vec<String>>,
    /// A Zenoh configuration file (JSON5) for everything else; the settings above and the
    /// service's own (module documentation) are applied on top of it.
    pub config_file: Option<PathBuf>,
}

impl Default for ZenohOptions {
    fn default() -> Self {
        ZenohOptions {
            mode: Mode::Peer,
            listen: Vec::new(),
            connect: Vec::new(),
            map_listen: None,
            map_connect: None,
            config_file: None,
        }
    }
}

/// The environment variable of Zenoh's runtime configuration.
pub const RUNTIME_ENV: &str = "ZENOH_RUNTIME";

/// `ZENOH_RUNTIME` handing every Zenoh runtime over to `rx` with one worker thread.
pub const ONE_WORKER_RUNTIME: &str = "(app: (handover: rx), acc: (handover: rx), tx: (handover: rx), net: (handover: rx), rx: (worker_threads: 1))";

/// Whether this process's `ZENOH_RUNTIME` is [`ONE_WORKER_RUNTIME`].
pub fn runtime_env_is_one_worker() -> bool {
    std::env::var(RUNTIME_ENV).is_ok_and(|v| v == ONE_WORKER_RUNTIME)
}

/// Sets `ZENOH_RUNTIME` to [`ONE_WORKER_RUNTIME`] unless it is set already (a user's choice
/// wins). Returns the value in effect.
///
/// # Safety
///
/// Call it only while the process has a single thread (first thing in `main`): changing the
/// environment races with any other thread reading it.
#[allow(unsafe_code)]
pub unsafe fn set_runtime_env_if_unset() -> String {
    match std::env::var(RUNTIME_ENV) {
        Ok(value) => value,
        Err(_) => {
            // SAFETY: the caller guarantees that no other thread runs.
            unsafe { std::env::set_var(RUNTIME_ENV, ONE_WORKER_RUNTIME) };
            ONE_WORKER_RUNTIME.to_string()
        }
    }
}

/// A configuration that cannot be built.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum ConfigError {
    /// The configuration file cannot be read or parsed.
    File {
        /// The file.
        path: PathBuf,
        /// Zenoh's message.
        detail: String,
    },
    /// An endpoint without a port to derive the map session's from.
    Endpoint {
        /// The endpoint.
        endpoint: String,
        /// What is wrong.
        why: &'static str,
    },
    /// Zenoh refused a setting.
    Setting {
        /// The configuration key.
        key: String,
        /// The value.
        value: String,
        /// Zenoh's message.
        detail: String,
    },
}

impl fmt::Display for ConfigError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ConfigError::File { path, detail } => {
                write!(f, "Zenoh configuration {}: {detail}", path.display())
            }
            ConfigError::Endpoint { endpoint, why } => write!(f, "endpoint {endpoint:?}: {why}"),
            ConfigError::Setting { key, value, detail } => {
                write!(f, "Zenoh setting {key} = {value}: {detail}")
            }
        }
    }
}

impl std::error::Error for ConfigError {}

/// `endpoint` with its port plus one: the map session's endpoint for a plan endpoint
/// (`tcp/127.0.0.1:7447` -> `tcp/127.0.0.1:7448`; port 0, "any free port", stays 0).
pub fn next_port(endpoint: &str) -> Result<String, ConfigError> {
    let bad = |why| ConfigError::Endpoint {
        endpoint: endpoint.to_string(),
        why,
    };
    // `proto/address[?metadata][#config]`: the port ends the address.
    let end = endpoint.find(['?', '#']).unwrap_or(endpoint.len());
    let (locator, tail) = endpoint.split_at(end);
    let (_, address) = locator
        .split_once('/')
        .ok_or_else(|| bad("expected PROTOCOL/HOST:PORT"))?;
    let colon = address
        .rfind(':')
        .ok_or_else(|| bad("expected PROTOCOL/HOST:PORT"))?;
    let port: u16 = address[colon + 1..]
        .parse()
        .map_err(|_| bad("the port is not a number from 0 to 65535"))?;
    let next = match port {
        0 => 0,
        65535 => return Err(bad("port 65535 has no next port for the map session")),
        p => p + 1,
    };
    let head = &locator[..locator.len() - (address.len() - colon - 1)];
    Ok(format!("{head}{next}{tail}"))
}

fn json_list(items: &[String]) -> String {
    let quoted: Vec<String> = items
        .iter()
        .map(|s| serde_json::Value::String(s.clone()).to_string())
        .collect();
    format!("[{}]", quoted.join(","))
}

fn set(config: &mut ::zenoh::Config, key: &str, value: &str) -> Result<(), ConfigError> {
    config
        .insert_json5(key, value)
        .map_err(|e| ConfigError::Setting {
            key: key.to_string(),
            value: value.to_string(),
            detail: e.to_string(),
        })
}

/// The configuration of one of a process's sessions (see the module documentation).
pub fn session_config(
    options: &ZenohOptions,
    kind: SessionKind,
) -> Result<::zenoh::Config, ConfigError> {
    let mut config = match &options.config_file {
        Some(path) => ::zenoh::Config::from_file(path).map_err(|e| ConfigError::File {
            path: path.clone(),
            detail: e.to_string(),
        })?,
        None => ::zenoh::Config::default(),
    };
    let derive = |list: &[String]| -> Result<Vec<String>, ConfigError> {
        list.iter().map(|e| next_port(e)).collect()
    };
    let (listen, connect) = match kind {
        SessionKind::Plan => (options.listen.clone(), options.connect.clone()),
        SessionKind::Map => (
            match &options.map_listen {
                Some(l) => l.clone(),
                None => derive(&options.listen)?,
            },
            match &options.map_connect {
                Some(c) => c.clone(),
                None => derive(&options.connect)?,
            },
        ),
    };
    set(
        &mut config,
        "mode",
        &format!("\"{}\"", options.mode.as_str()),
    )?;
    // Only the endpoints given: no listening on every interface by default.
    set(&mut config, "listen/endpoints", &json_list(&listen))?;
    set(&mut config, "connect/endpoints", &json_list(&connect))?;
    set(&mut config, "scouting/multicast/enabled", "false")?;
    set(
        &mut config,
        "connect/retry",
        "{period_init_ms: 100, period_max_ms: 1000, period_increase_factor: 2}",
    )?;
    let lowlatency = kind == SessionKind::Plan;
    set(
        &mut config,
        "transport/unicast/lowlatency",
        if lowlatency { "true" } else { "false" },
    )?;
    set(
        &mut config,
        "transport/unicast/qos/enabled",
        if lowlatency { "false" } else { "true" },
    )?;
    Ok(config)
}

/// Sets the largest message a map session accepts (`transport/link/rx/max_message_size`).
pub fn set_max_message_size(config: &mut ::zenoh::Config, bytes: usize) -> Result<(), ConfigError> {
    set(
        config,
        "transport/link/rx/max_message_size",
        &bytes.to_string(),
    )
}

/// The largest message a session configured by `config` accepts.
pub fn max_message_size(config: &::zenoh::Config) -> Option<usize> {
    config
        .get_json("transport/link/rx/max_message_size")
        .ok()?
        .trim()
        .parse()
        .ok()
}

/// A port of `127.0.0.1` free now whose next port is free too (a plan endpoint and its map
/// endpoint): for tests and for a private server. Another process may still take it before
/// it is bound.
pub fn free_port_pair() -> std::io::Result<u16> {
    use std::net::TcpListener;
    for _ in 0..200 {
        let first = TcpListener::bind("127.0.0.1:0")?;
        let port = first.local_addr()?.port();
        if port < u16::MAX && TcpListener::bind(("127.0.0.1", port + 1)).is_ok() {
            return Ok(port);
        }
    }
    Err(std::io::Error::new(
        std::io::ErrorKind::AddrInUse,
        "no two consecutive free ports on 127.0.0.1",
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn map_endpoints_take_the_next_port() {
        assert_eq!(
            next_port("tcp/127.0.0.1:7447").unwrap(),
            "tcp/127.0.0.1:7448"
        );
        assert_eq!(next_port("tcp/[::1]:7447").unwrap(), "tcp/[::1]:7448");
        assert_eq!(next_port("tcp/0.0.0.0:0").unwrap(), "tcp/0.0.0.0:0");
        assert_eq!(
            next_port("tcp/localhost:80?iface=lo#rel=1").unwrap(),
            "tcp/localhost:81?iface=lo#rel=1"
        );
        for bad in [
            "tcp/127.0.0.1",
            "127.0.0.1:7447",
            "tcp/h:x",
            "tcp/h:65535",
            "tcp/h:70000",
        ] {
            assert!(
                matches!(next_port(bad), Err(ConfigError::Endpoint { .. })),
                "{bad}"
            );
        }
    }

    #[test]
    fn sessions_get_the_service_settings() {
        let options = ZenohOptions {
            mode: Mode::Client,
            connect: vec!["tcp/127.0.0.1:7447".into()],
            ..ZenohOptions::default()
        };
        let plan = session_config(&options, SessionKind::Plan).unwrap();
        let get = |c: &::zenoh::Config, k: &str| c.get_json(k).unwrap();
        assert_eq!(get(&plan, "mode"), "\"client\"");
        assert_eq!(get(&plan, "transport/unicast/lowlatency"), "true");
        assert_eq!(get(&plan, "transport/unicast/qos/enabled"), "false");
        assert_eq!(get(&plan, "scouting/multicast/enabled"), "false");
        assert_eq!(get(&plan, "connect/endpoints"), "[\"tcp/127.0.0.1:7447\"]");
        let mut map = session_config(&options, SessionKind::Map).unwrap();
        assert_eq!(get(&map, "transport/unicast/lowlatency"), "false");
        assert_eq!(get(&map, "connect/endpoints"), "[\"tcp/127.0.0.1:7448\"]");
        set_max_message_size(&mut map, 3 << 20).unwrap();
        assert_eq!(max_message_size(&map), Some(3 << 20));
        let missing = ZenohOptions {
            config_file: Some("/nonexistent/zenoh.json5".into()),
            ..options
        };
        assert!(matches!(
            session_config(&missing, SessionKind::Plan),
            Err(ConfigError::File { .. })
        ));
    }
}
