//! The therapist's messages kept in the station's home (`messages.json`): what the hub sent,
//! which one the next session's start card shows (so it shows even when the hub is
//! unreachable then), when each was shown, and whether the hub has confirmed that.

use netlink::{Message, MessageSeen};
use serde::{Deserialize, Serialize};
use session::files::write_private;
use std::path::{Path, PathBuf};

/// Most messages kept; beyond it the oldest seen and confirmed ones are forgotten.
pub const MAX_KEPT: usize = 50;

/// One message as the station keeps it.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Kept {
    /// The hub's id.
    pub id: String,
    /// The text (checked again on load: plain text, at most 500 characters).
    pub text: String,
    /// When the therapist wrote it (hub clock), ms since the Unix epoch.
    pub sent_unix_ms: u64,
    /// When it was first drawn on the patient's screen, ms since the Unix epoch.
    #[serde(default)]
    pub seen_unix_ms: Option<u64>,
    /// The hub confirmed (a `Bye` reply) a connection that carried the "seen".
    #[serde(default)]
    pub seen_confirmed: bool,
}

/// The messages in a home.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Inbox {
    path: PathBuf,
    /// Oldest first.
    pub kept: Vec<Kept>,
}

impl Inbox {
    /// The messages kept at `path` (none if the file is missing; an unreadable file is
    /// reported and read as none, and one with a text the protocol refuses drops it).
    pub fn load(path: &Path) -> Self {
        let kept = match std::fs::read(path) {
            Ok(bytes) => serde_json::from_slice::<Vec<Kept>>(&bytes).unwrap_or_else(|e| {
                tracing::warn!(
                    "{} is not a list of messages ({e}); none kept",
                    path.display()
                );
                Vec::new()
            }),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Vec::new(),
            Err(e) => {
                tracing::warn!("cannot read {}: {e}", path.display());
                Vec::new()
            }
        };
        let kept = kept
            .into_iter()
            .filter(|k| netlink::check_message_text(&k.text).is_ok())
            .collect();
        Self {
            path: path.to_owned(),
            kept,
        }
    }

    /// Keeps `message` unless one with its id is kept already; true if it was new.
    pub fn add(&mut self, message: Message) -> bool {
        if self.kept.iter().any(|k| k.id == message.id) {
            return false;
        }
        self.kept.push(Kept {
            id: message.id,
            text: message.text,
            sent_unix_ms: message.sent_unix_ms,
            seen_unix_ms: None,
            seen_confirmed: false,
        });
        self.kept.sort_by_key(|k| k.sent_unix_ms);
        let excess = self.kept.len().saturating_sub(MAX_KEPT);
        let mut dropped = 0;
        self.kept.retain(|k| {
            let drop = dropped < excess && k.seen_confirmed;
            dropped += usize::from(drop);
            !drop
        });
        true
    }

    /// The message the next start card shows: the newest not yet seen.
    pub fn to_show(&self) -> Option<&Kept> {
        self.kept.iter().rev().find(|k| k.seen_unix_ms.is_none())
    }

    /// Message `id` was drawn on the screen at `at_ms` (the first time counts); its "seen".
    pub fn mark_seen(&mut self, id: &str, at_ms: u64) -> Option<MessageSeen> {
        let k = self.kept.iter_mut().find(|k| k.id == id)?;
        let at = *k.seen_unix_ms.get_or_insert(at_ms);
        Some(MessageSeen {
            id: k.id.clone(),
            seen_unix_ms: at,
        })
    }

    /// The "seen" of every message shown but not confirmed by the hub, to say again.
    pub fn unconfirmed(&self) -> Vec<MessageSeen> {
        self.kept
            .iter()
            .filter(|k| !k.seen_confirmed)
            .filter_map(|k| {
                k.seen_unix_ms.map(|at| MessageSeen {
                    id: k.id.clone(),
                    seen_unix_ms: at,
                })
            })
            .collect()
    }

    /// The hub confirmed a connection that carried these "seen".
    pub fn confirm(&mut self, seen: &[MessageSeen]) {
        for k in &mut self.kept {
            if seen.iter().any(|s| s.id == k.id) {
                k.seen_confirmed = true;
            }
        }
    }

    /// Keeps each of `messages` (received on a connection other than a session's live link:
    /// an upload's, a queued session's) as the live link's are kept: once, by id, unseen
    /// until a start card shows it. Saved if any was new; true then.
    pub fn keep_received(&mut self, messages: impl IntoIterator<Item = Message>) -> bool {
        let mut new = false;
        for m in messages {
            new |= self.add(m);
        }
        if new && let Err(e) = self.save() {
            tracing::warn!("the therapist's messages are not kept: {e:#}");
        }
        new
    }

    /// Writes the messages back (0600).
    pub fn save(&self) -> anyhow::Result<()> {
        write_private(&self.path, &serde_json::to_vec_pretty(&self.kept)?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn message(id: &str, sent_unix_ms: u64) -> Message {
        Message {
            id: id.into(),
            text: format!("note {id}"),
            sent_unix_ms,
        }
    }

    #[test]
    fn the_newest_unseen_message_shows_and_its_seen_is_said_until_confirmed_across_restarts() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("messages.json");
        let mut inbox = Inbox::load(&path);
        assert!(inbox.add(message("m-1", 10)));
        assert!(inbox.add(message("m-2", 20)));
        assert!(!inbox.add(message("m-1", 10)), "kept once, by id");
        assert_eq!(inbox.to_show().unwrap().id, "m-2");
        let seen = inbox.mark_seen("m-2", 1_000).unwrap();
        assert_eq!(
            inbox.mark_seen("m-2", 2_000).unwrap(),
            seen,
            "first time counts"
        );
        inbox.save().unwrap();
        // The hub unreachable: the next start still has the older one to show, and the seen
        // of m-2 waits to be said.
        let mut again = Inbox::load(&path);
        assert_eq!(again.to_show().unwrap().id, "m-1");
        assert_eq!(again.unconfirmed(), vec![seen.clone()]);
        again.confirm(&[seen]);
        assert!(again.unconfirmed().is_empty());
        std::fs::write(&path, b"not json").unwrap();
        assert_eq!(Inbox::load(&path).kept, Vec::new());
    }
}
