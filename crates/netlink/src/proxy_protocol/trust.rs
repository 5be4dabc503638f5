//! Which peers may send a PROXY protocol header: the load balancers a clinic names
//! (`proxy_protocol_from = ["10.0.0.0/8"]`). Only a connection from one of them is read for a
//! header; from any other address a header is never parsed, so a client cannot claim another
//! address.

use std::fmt;
use std::net::IpAddr;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

/// One network: an address and how many of its leading bits are fixed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Cidr {
    network: IpAddr,
    prefix_bits: u8,
}

impl Cidr {
    /// Whether `ip` is in this network (an IPv4-mapped IPv6 address counts as its IPv4 one).
    pub fn contains(&self, ip: IpAddr) -> bool {
        match (self.network, ip.to_canonical()) {
            (IpAddr::V4(net), IpAddr::V4(ip)) => {
                mask(u128::from(u32::from(ip)) << 96, self.prefix_bits)
                    == u128::from(u32::from(net)) << 96
            }
            (IpAddr::V6(net), IpAddr::V6(ip)) => {
                mask(u128::from(ip), self.prefix_bits) == u128::from(net)
            }
            _ => false,
        }
    }
}

/// `bits` with all but its leading `prefix_bits` cleared.
fn mask(bits: u128, prefix_bits: u8) -> u128 {
    match prefix_bits {
        0 => 0,
        p => bits & (u128::MAX << (128 - u32::from(p))),
    }
}

impl FromStr for Cidr {
    type Err = String;

    /// `10.0.0.0/8`, `2001:db8::/32`, or one address (`127.0.0.1` is `127.0.0.1/32`).
    fn from_str(s: &str) -> Result<Self, String> {
        let (address, prefix) = match s.split_once('/') {
            Some((a, p)) => (a, Some(p)),
            None => (s, None),
        };
        let network: IpAddr = address.trim().parse().map_err(|_| {
            format!("`{s}` is not an address or network (e.g. `10.0.0.0/8`, `127.0.0.1`)")
        })?;
        let network = network.to_canonical();
        let width: u8 = if network.is_ipv4() { 32 } else { 128 };
        let prefix_bits = match prefix {
            None => width,
            Some(p) => p
                .trim()
                .parse::<u8>()
                .ok()
                .filter(|p| *p <= width)
                .ok_or_else(|| {
                    format!("`{s}`: the prefix length must be a number in [1, {width}]")
                })?,
        };
        if prefix_bits == 0 {
            return Err(format!(
                "`{s}` would trust every address: any client could then claim any address; \
                 name the load balancers' addresses"
            ));
        }
        let cidr = Self {
            network,
            prefix_bits,
        };
        if cidr.host_bits_set() {
            return Err(format!(
                "`{s}` has bits set past its /{prefix_bits} prefix; write the network's first \
                 address (e.g. `10.0.0.0/8`)"
            ));
        }
        Ok(cidr)
    }
}

impl Cidr {
    fn host_bits_set(&self) -> bool {
        let bits = match self.network {
            IpAddr::V4(a) => u128::from(u32::from(a)) << 96,
            IpAddr::V6(a) => u128::from(a),
        };
        mask(bits, self.prefix_bits) != bits
    }
}

impl fmt::Display for Cidr {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.network, self.prefix_bits)
    }
}

/// The peers whose connections must start with a PROXY protocol header; empty (the default):
/// nobody's, every connection's address is its own.
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "Vec<String>", into = "Vec<String>")]
pub struct TrustedProxies(Vec<Cidr>);

impl TrustedProxies {
    /// Parses each entry (see [`Cidr`]); the error names the entry and what is wrong.
    pub fn parse<S: AsRef<str>>(entries: &[S]) -> Result<Self, String> {
        entries
            .iter()
            .map(|e| e.as_ref().parse::<Cidr>())
            .collect::<Result<Vec<_>, _>>()
            .map(Self)
    }

    /// Whether a connection from `ip` must carry a header (and only then is one read).
    pub fn trusts(&self, ip: IpAddr) -> bool {
        self.0.iter().any(|c| c.contains(ip))
    }

    /// Whether no peer is trusted.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

impl TryFrom<Vec<String>> for TrustedProxies {
    type Error = String;

    fn try_from(entries: Vec<String>) -> Result<Self, String> {
        Self::parse(&entries)
    }
}

impl From<TrustedProxies> for Vec<String> {
    fn from(t: TrustedProxies) -> Self {
        t.0.iter().map(ToString::to_string).collect()
    }
}

impl fmt::Display for TrustedProxies {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let list: Vec<String> = self.clone().into();
        write!(f, "[{}]", list.join(", "))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ip(s: &str) -> IpAddr {
        s.parse().unwrap()
    }

    #[test]
    fn only_the_named_networks_are_trusted() {
        let t =
            TrustedProxies::parse(&["127.0.0.1/32", "10.0.0.0/8", "2001:db8::/32", "192.0.2.7"])
                .unwrap();
        for yes in [
            "127.0.0.1",
            "10.0.0.1",
            "10.255.255.255",
            "2001:db8::1",
            "192.0.2.7",
            "::ffff:10.2.3.4",
        ] {
            assert!(t.trusts(ip(yes)), "{yes}");
        }
        for no in [
            "127.0.0.2",
            "11.0.0.1",
            "9.255.255.255",
            "2001:db9::1",
            "192.0.2.8",
            "::1",
            "::ffff:127.0.0.2",
        ] {
            assert!(!t.trusts(ip(no)), "{no}");
        }
        assert!(!TrustedProxies::default().trusts(ip("127.0.0.1")));
        assert_eq!(
            t.to_string(),
            "[127.0.0.1/32, 10.0.0.0/8, 2001:db8::/32, 192.0.2.7/32]"
        );
    }

    #[test]
    fn bad_entries_are_named_with_what_is_wrong() {
        for (entry, says) in [
            ("10.0.0.0/33", "[1, 32]"),
            ("::/129", "[1, 128]"),
            ("10.0.0.0/x", "prefix length"),
            ("balancer.local", "not an address"),
            ("0.0.0.0/0", "every address"),
            ("::/0", "every address"),
            ("10.0.0.1/8", "`10.0.0.0/8`"),
            ("", "not an address"),
        ] {
            let e = TrustedProxies::parse(&["127.0.0.1", entry]).unwrap_err();
            assert!(
                e.contains(&format!("`{entry}`")) && e.contains(says),
                "{entry}: {e}"
            );
        }
    }

    #[test]
    fn it_reads_and_writes_as_a_list_of_strings() {
        #[derive(Debug, Serialize, Deserialize, PartialEq)]
        struct Network {
            proxy_protocol_from: TrustedProxies,
        }
        let n: Network =
            serde_json::from_str(r#"{"proxy_protocol_from": ["10.0.0.0/8", "::1"]}"#).unwrap();
        assert!(n.proxy_protocol_from.trusts(ip("10.9.9.9")));
        assert!(n.proxy_protocol_from.trusts(ip("::1")));
        let again: Network = serde_json::from_str(&serde_json::to_string(&n).unwrap()).unwrap();
        assert_eq!(again, n);
        let e = serde_json::from_str::<Network>(r#"{"proxy_protocol_from": ["10.0.0.0/99"]}"#)
            .unwrap_err()
            .to_string();
        assert!(e.contains("`10.0.0.0/99`"), "{e}");
    }
}
