//! The key expressions of the planner service over Zenoh.
//!
//! Every key lives under the service prefix `P` and a protocol version chunk, `@v1`: a chunk
//! starting with `@` is *verbatim* in Zenoh, so no wildcard (`P/*/plan`, `P/**`) matches it,
//! and a client of another protocol version never reaches these queryables by accident.
//!
//! | key | what |
//! |---|---|
//! | `P/@v1/plan` | the plan queryable (complete), one per planner |
//! | `P/@v1/info/<zid>` | a planner's limits ([`PlannerInfo`](super::PlannerInfo)), a queryable |
//! | `P/@v1/alive/<zid>` | a planner's liveliness token |
//! | `P/@v1/map/<id>` | map `id`: the owner's publisher, and its queryable answering the latest version |
//! | `P/@v1/req/<zid>/<client>` | requests of the publish-subscribe pair to planner `<zid>` (subscriber) |
//! | `P/@v1/rep/<client>` | the pair's answers to client `<client>` (its subscriber) |

use std::fmt;

/// The protocol version chunk of every key (verbatim: wildcards cannot match it).
pub const VERSION_CHUNK: &str = "@v1";

/// The longest service prefix, bytes (keys travel in every message of the low-latency
/// transport, whose messages are bounded).
pub const MAX_PREFIX: usize = 200;

/// A service prefix that cannot be used in a key expression.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BadPrefix {
    /// The prefix given.
    pub prefix: String,
    /// What is wrong with it.
    pub why: &'static str,
}

impl fmt::Display for BadPrefix {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "service prefix {:?}: {}", self.prefix, self.why)
    }
}

impl std::error::Error for BadPrefix {}

/// The keys of one service prefix.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Keys {
    prefix: String,
    root: String,
}

impl Keys {
    /// The keys under `prefix` (one or more `/`-separated chunks of letters, digits, `-`,
    /// `_` and `.`; no wildcard, no verbatim `@` chunk, no empty chunk).
    pub fn new(prefix: &str) -> Result<Self, BadPrefix> {
        let bad = |why| BadPrefix {
            prefix: prefix.to_string(),
            why,
        };
        if prefix.is_empty() {
            return Err(bad("it is empty"));
        }
        if prefix.len() > MAX_PREFIX {
            return Err(bad("it is longer than 200 bytes"));
        }
        for chunk in prefix.split('/') {
            if chunk.is_empty() {
                return Err(bad(
                    "it has an empty chunk (a leading, trailing or double '/')",
                ));
            }
            if !chunk
                .bytes()
                .all(|b| b.is_ascii_alphanumeric() || matches!(b, b'-' | b'_' | b'.'))
            {
                return Err(bad(
                    "a chunk may hold only letters, digits, '-', '_' and '.' (no wildcard, no '@')",
                ));
            }
        }
        Ok(Keys {
            prefix: prefix.to_string(),
            root: format!("{prefix}/{VERSION_CHUNK}"),
        })
    }

    /// The service prefix.
    pub fn prefix(&self) -> &str {
        &self.prefix
    }

    /// `P/@v1/plan`: the plan queryable.
    pub fn plan(&self) -> String {
        format!("{}/plan", self.root)
    }

    /// `P/@v1/map/<id>`: map `id`'s publisher and latest-version queryable.
    pub fn map(&self, map_id: u32) -> String {
        format!("{}/map/{map_id}", self.root)
    }

    /// `P/@v1/map/*`: every map (what a planner subscribes to).
    pub fn maps(&self) -> String {
        format!("{}/map/*", self.root)
    }

    /// The map id of a key under [`maps`](Self::maps); `None` for any other key.
    pub fn map_id_of(&self, key: &str) -> Option<u32> {
        let rest = key.strip_prefix(&self.root)?.strip_prefix("/map/")?;
        // Canonical decimal only: "01" or "+1" would be another key for the same id.
        let id: u32 = rest.parse().ok()?;
        (id.to_string() == rest).then_some(id)
    }

    /// `P/@v1/alive/<zid>`: a planner's liveliness token.
    pub fn alive(&self, zid: &str) -> String {
        format!("{}/alive/{zid}", self.root)
    }

    /// `P/@v1/alive/*`: every planner's token.
    pub fn alive_all(&self) -> String {
        format!("{}/alive/*", self.root)
    }

    /// `P/@v1/req/<zid>/<client>`: a pair request of `client` to planner `zid`.
    pub fn request(&self, zid: &str, client: &str) -> String {
        format!("{}/req/{zid}/{client}", self.root)
    }

    /// `P/@v1/req/<zid>/*`: every pair request to planner `zid`.
    pub fn requests_to(&self, zid: &str) -> String {
        format!("{}/req/{zid}/*", self.root)
    }

    /// The client of a key under [`requests_to`](Self::requests_to)`(zid)`.
    pub fn client_of<'k>(&self, zid: &str, key: &'k str) -> Option<&'k str> {
        let rest = key.strip_prefix(&self.root)?.strip_prefix("/req/")?;
        let client = rest.strip_prefix(zid)?.strip_prefix('/')?;
        (!client.is_empty() && !client.contains('/')).then_some(client)
    }

    /// `P/@v1/rep/<client>`: the pair's answers to `client`.
    pub fn reply(&self, client: &str) -> String {
        format!("{}/rep/{client}", self.root)
    }

    /// `P/@v1/info/<zid>`: a planner's limits.
    pub fn info(&self, zid: &str) -> String {
        format!("{}/info/{zid}", self.root)
    }

    /// `P/@v1/info/*`: every planner's limits.
    pub fn info_all(&self) -> String {
        format!("{}/info/*", self.root)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ::zenoh::key_expr::KeyExpr;

    #[test]
    fn keys_are_valid_and_versioned() {
        let k = Keys::new("fleet/planner").unwrap();
        assert_eq!(k.plan(), "fleet/planner/@v1/plan");
        assert_eq!(k.map(7), "fleet/planner/@v1/map/7");
        assert_eq!(k.alive("abc"), "fleet/planner/@v1/alive/abc");
        for key in [k.plan(), k.map(7), k.maps(), k.alive_all(), k.info_all()] {
            KeyExpr::try_from(key.as_str()).unwrap();
        }
        assert_eq!(k.map_id_of("fleet/planner/@v1/map/7"), Some(7));
        assert_eq!(k.map_id_of("fleet/planner/@v1/map/07"), None);
        assert_eq!(k.map_id_of("fleet/planner/@v1/map/4294967296"), None);
        assert_eq!(k.map_id_of("fleet/planner/@v2/map/7"), None);
        assert_eq!(k.request("z1", "c9"), "fleet/planner/@v1/req/z1/c9");
        assert_eq!(k.client_of("z1", &k.request("z1", "c9")), Some("c9"));
        assert_eq!(k.client_of("z2", &k.request("z1", "c9")), None);
        assert_eq!(k.client_of("z1", "fleet/planner/@v1/req/z1/c9/x"), None);
        assert_eq!(k.reply("c9"), "fleet/planner/@v1/rep/c9");
        // Wildcards do not reach the verbatim version chunk.
        let any = KeyExpr::try_from("fleet/planner/**").unwrap();
        let plan = KeyExpr::try_from(k.plan()).unwrap();
        assert!(!any.intersects(&plan));
        let versioned_any = KeyExpr::try_from("fleet/planner/@v1/**").unwrap();
        assert!(versioned_any.intersects(&plan));
    }

    #[test]
    fn bad_prefixes_are_refused_with_the_reason() {
        for p in [
            "", "a//b", "/a", "a/", "a/*", "a/**", "a/@v1", "a b", "a$*", "a?b", "a#b",
        ] {
            let e = Keys::new(p).unwrap_err();
            assert_eq!(e.prefix, p);
        }
        assert!(Keys::new(&"p".repeat(MAX_PREFIX + 1)).is_err());
        assert!(Keys::new(&"p".repeat(MAX_PREFIX)).is_ok());
        assert!(Keys::new("planner").is_ok());
        assert!(Keys::new("site-3/fleet_a/planner.v2").is_ok());
    }
}
