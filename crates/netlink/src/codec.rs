//! The wire format (pure: no I/O). See `PROTOCOL.md` for the normative description.
//!
//! ```text
//! offset size field
//! 0      4    magic   b"TRHB"
//! 4      2    version u16 big-endian (= HEADER_VERSION, 1)
//! 6      1    kind    u8 (FrameKind)
//! 7      1    flags   u8, reserved, must be 0
//! 8      4    length  u32 big-endian, payload bytes, ≤ MAX_PAYLOAD_LEN
//! 12     len  payload JSON (UTF-8) of the frame body
//! ```

use crate::frame::{Frame, FrameKind};

/// The header's `version`: the framing's version, 1 for every frame of protocol versions 1
/// and 2 (version 2 only adds frame kinds, sent only on connections negotiated at 2; see
/// [`crate::frame::MESSAGES_VERSION`]).
pub const HEADER_VERSION: u16 = 1;

/// The four bytes every frame starts with.
pub const MAGIC: [u8; 4] = *b"TRHB";

/// Header length in bytes.
pub const HEADER_LEN: usize = 12;

/// Largest payload accepted or produced, bytes (64 KiB).
pub const MAX_PAYLOAD_LEN: usize = 64 * 1024;

/// Why bytes could not be decoded into a frame, or a frame could not be encoded.
///
/// After a decode error the byte stream has lost its framing: close the connection.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CodecError {
    /// The stream does not start with `TRHB`.
    #[error("bad magic {found:02x?}: expected \"TRHB\" (54 52 48 42); not a telerehab peer?")]
    BadMagic {
        /// The bytes found (up to four).
        found: Vec<u8>,
    },
    /// The peer speaks another protocol version.
    #[error("unsupported protocol version {found}; this side speaks only {supported}")]
    UnsupportedVersion {
        /// Version in the header.
        found: u16,
        /// Version this crate speaks.
        supported: u16,
    },
    /// The kind byte names no frame kind.
    #[error("unknown frame kind {0} (known kinds 1..=15)")]
    UnknownKind(u8),
    /// Reserved flag bits are set.
    #[error("reserved flags 0x{0:02x} set; version 1 requires flags = 0")]
    ReservedFlags(u8),
    /// The payload is larger than [`MAX_PAYLOAD_LEN`].
    #[error("payload of {len} bytes exceeds the maximum of {max} bytes")]
    Oversize {
        /// Announced or produced payload length.
        len: usize,
        /// [`MAX_PAYLOAD_LEN`].
        max: usize,
    },
    /// The payload is not valid JSON for the kind's body.
    #[error("bad JSON in {kind} payload: {source}")]
    BadJson {
        /// Kind from the header.
        kind: FrameKind,
        /// The JSON error.
        source: serde_json::Error,
    },
    /// The body decoded but a field is invalid (the message names it).
    #[error("invalid {kind} frame: {reason}")]
    Invalid {
        /// Kind of the frame.
        kind: FrameKind,
        /// Which field, and its allowed range.
        reason: crate::frame::FieldError,
    },
}

/// Appends the encoded `frame` to `out`. On error `out` is left as it was.
///
/// The body is validated first ([`Frame::validate`]) so a peer never receives a frame it
/// would reject.
pub fn encode(frame: &Frame, out: &mut Vec<u8>) -> Result<(), CodecError> {
    let kind = frame.kind();
    frame
        .validate()
        .map_err(|reason| CodecError::Invalid { kind, reason })?;
    let start = out.len();
    out.extend_from_slice(&MAGIC);
    out.extend_from_slice(&HEADER_VERSION.to_be_bytes());
    out.push(kind.byte());
    out.push(0);
    out.extend_from_slice(&[0; 4]);
    let written = match frame {
        Frame::Hello(b) => serde_json::to_writer(&mut *out, b),
        Frame::Summary(b) => serde_json::to_writer(&mut *out, b),
        Frame::Ack(b) => serde_json::to_writer(&mut *out, b),
        Frame::Regimen(b) => serde_json::to_writer(&mut *out, b),
        Frame::Bye(b) => serde_json::to_writer(&mut *out, b),
        Frame::Error(b) => serde_json::to_writer(&mut *out, b),
        Frame::PairStart(b) => serde_json::to_writer(&mut *out, b),
        Frame::PairChallenge(b) => serde_json::to_writer(&mut *out, b),
        Frame::PairFinish(b) => serde_json::to_writer(&mut *out, b),
        Frame::Paired(b) => serde_json::to_writer(&mut *out, b),
        Frame::UploadStart(b) => serde_json::to_writer(&mut *out, b),
        Frame::UploadAt(b) => serde_json::to_writer(&mut *out, b),
        Frame::UploadChunk(b) => serde_json::to_writer(&mut *out, b),
        Frame::Message(b) => serde_json::to_writer(&mut *out, b),
        Frame::MessageSeen(b) => serde_json::to_writer(&mut *out, b),
        Frame::Care(b) => serde_json::to_writer(&mut *out, b),
    };
    let len = out.len() - start - HEADER_LEN;
    if let Err(source) = written {
        out.truncate(start);
        return Err(CodecError::BadJson { kind, source });
    }
    if len > MAX_PAYLOAD_LEN {
        out.truncate(start);
        return Err(CodecError::Oversize {
            len,
            max: MAX_PAYLOAD_LEN,
        });
    }
    // `len` ≤ MAX_PAYLOAD_LEN, so it fits in u32.
    out[start + 8..start + HEADER_LEN].copy_from_slice(&(len as u32).to_be_bytes());
    Ok(())
}

/// Encodes `frame` into a new buffer.
pub fn encode_to_vec(frame: &Frame) -> Result<Vec<u8>, CodecError> {
    let mut out = Vec::with_capacity(256);
    encode(frame, &mut out)?;
    Ok(out)
}

/// Decodes the first frame in `buf`.
///
/// Returns `Ok(None)` if `buf` holds only a prefix of a frame (read more bytes), or the frame
/// and the number of bytes it used. Header errors are reported as soon as the offending byte
/// is present: a wrong magic after the first byte, an oversize length before its payload.
pub fn decode(buf: &[u8]) -> Result<Option<(Frame, usize)>, CodecError> {
    let magic_len = buf.len().min(MAGIC.len());
    if buf[..magic_len] != MAGIC[..magic_len] {
        return Err(CodecError::BadMagic {
            found: buf[..magic_len].to_vec(),
        });
    }
    if buf.len() >= 6 {
        let version = u16::from_be_bytes([buf[4], buf[5]]);
        if version != HEADER_VERSION {
            return Err(CodecError::UnsupportedVersion {
                found: version,
                supported: HEADER_VERSION,
            });
        }
    }
    if buf.len() >= 7 && FrameKind::from_byte(buf[6]).is_none() {
        return Err(CodecError::UnknownKind(buf[6]));
    }
    if buf.len() >= 8 && buf[7] != 0 {
        return Err(CodecError::ReservedFlags(buf[7]));
    }
    if buf.len() < HEADER_LEN {
        return Ok(None);
    }
    let len = u32::from_be_bytes([buf[8], buf[9], buf[10], buf[11]]) as usize;
    if len > MAX_PAYLOAD_LEN {
        return Err(CodecError::Oversize {
            len,
            max: MAX_PAYLOAD_LEN,
        });
    }
    let total = HEADER_LEN + len;
    if buf.len() < total {
        return Ok(None);
    }
    let Some(kind) = FrameKind::from_byte(buf[6]) else {
        return Err(CodecError::UnknownKind(buf[6]));
    };
    let payload = &buf[HEADER_LEN..total];
    fn body<T: serde::de::DeserializeOwned>(
        kind: FrameKind,
        payload: &[u8],
    ) -> Result<T, CodecError> {
        serde_json::from_slice(payload).map_err(|source| CodecError::BadJson { kind, source })
    }
    let frame = match kind {
        FrameKind::Hello => Frame::Hello(body(kind, payload)?),
        FrameKind::Summary => Frame::Summary(body(kind, payload)?),
        FrameKind::Ack => Frame::Ack(body(kind, payload)?),
        FrameKind::Regimen => Frame::Regimen(body(kind, payload)?),
        FrameKind::Bye => Frame::Bye(body(kind, payload)?),
        FrameKind::Error => Frame::Error(body(kind, payload)?),
        FrameKind::PairStart => Frame::PairStart(body(kind, payload)?),
        FrameKind::PairChallenge => Frame::PairChallenge(body(kind, payload)?),
        FrameKind::PairFinish => Frame::PairFinish(body(kind, payload)?),
        FrameKind::Paired => Frame::Paired(body(kind, payload)?),
        FrameKind::UploadStart => Frame::UploadStart(body(kind, payload)?),
        FrameKind::UploadAt => Frame::UploadAt(body(kind, payload)?),
        FrameKind::UploadChunk => Frame::UploadChunk(body(kind, payload)?),
        FrameKind::Message => Frame::Message(body(kind, payload)?),
        FrameKind::MessageSeen => Frame::MessageSeen(body(kind, payload)?),
        FrameKind::Care => Frame::Care(body(kind, payload)?),
    };
    frame
        .validate()
        .map_err(|reason| CodecError::Invalid { kind, reason })?;
    Ok(Some((frame, total)))
}

/// Incremental decoder: feed it bytes as they arrive, take frames out as they complete.
#[derive(Debug, Default)]
pub struct FrameDecoder {
    buf: Vec<u8>,
    start: usize,
}

impl FrameDecoder {
    /// An empty decoder.
    pub fn new() -> Self {
        Self::default()
    }

    /// Appends received bytes.
    pub fn extend(&mut self, bytes: &[u8]) {
        if self.start > 0 && self.start == self.buf.len() {
            self.buf.clear();
            self.start = 0;
        }
        self.buf.extend_from_slice(bytes);
    }

    /// The next complete frame, `Ok(None)` if more bytes are needed.
    ///
    /// After an error the stream's framing is lost; the decoder keeps returning errors.
    pub fn next_frame(&mut self) -> Result<Option<Frame>, CodecError> {
        match decode(&self.buf[self.start..])? {
            Some((frame, used)) => {
                self.start += used;
                if self.start == self.buf.len() {
                    self.buf.clear();
                    self.start = 0;
                } else if self.start > MAX_PAYLOAD_LEN {
                    self.buf.drain(..self.start);
                    self.start = 0;
                }
                Ok(Some(frame))
            }
            None => Ok(None),
        }
    }

    /// Bytes received but not yet returned as frames.
    pub fn buffered_len(&self) -> usize {
        self.buf.len() - self.start
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::frame::tests::summary;
    use crate::frame::{Ack, Bye, ErrorFrame, Hello, Regimen, Summary};
    use proptest::prelude::*;

    /// A Paired frame as hubs before the pseudonym sent it.
    const PAIRED_OLD_GOLDEN: &str = r#"TRHB\x00\x01\x0a\x00\x00\x00\x00\xaf{"station_id":"st-1","patient_id":"p-0042","ca_pem":"CA","cert_pem":"CERT","server_name":"hub.clinic","mac":"abababababababababababababababababababababababababababababababab"}"#;
    /// The same with the pseudonym.
    const PAIRED_NEW_GOLDEN: &str = r#"TRHB\x00\x01\x0a\x00\x00\x00\x00\xcc{"station_id":"st-1","patient_id":"p-0042","ca_pem":"CA","cert_pem":"CERT","server_name":"hub.clinic","mac":"abababababababababababababababababababababababababababababababab","patient_pseudonym":"P-0042"}"#;

    /// A version-1 station's Hello (the golden bytes are version 1's).
    fn hello() -> Hello {
        Hello {
            protocol_version: 1,
            station_id: "station-01".into(),
            patient_id: "p-0042".into(),
            session_id: "2026-11-21T09-30-00Z".into(),
            exercise: "sine-road".into(),
            started_unix_ms: 1_795_253_400_000,
            software_version: "telerehab 0.1.0".into(),
            min_protocol_version: None,
            wheel: None,
        }
    }

    fn one_of_each() -> Vec<Frame> {
        let mut s = summary("2026-11-21T09-30-00Z", 7);
        s.extra.insert("assist_level".into(), 0.5);
        vec![
            Frame::Hello(hello()),
            Frame::Summary(s),
            Frame::Ack(Ack {
                session_id: "2026-11-21T09-30-00Z".into(),
                seq: 7,
            }),
            Frame::Regimen(Regimen {
                id: "reg-3".into(),
                toml: "[exercise]\nname = \"sine-road\"\n".into(),
                prescribed_by: None,
            }),
            Frame::Bye(Bye {
                session_id: "2026-11-21T09-30-00Z".into(),
                reason: "session complete".into(),
                final_seq: Some(7),
                measures: Default::default(),
                hub_unix_ms: None,
                checkin: None,
                difficulty: None,
                exercises: Vec::new(),
            }),
            Frame::Error(ErrorFrame {
                message: "bad magic".into(),
                code: None,
            }),
        ]
    }

    /// Renders bytes as printable ASCII with `\xNN` escapes, for readable snapshots.
    fn escape(bytes: &[u8]) -> String {
        bytes
            .iter()
            .map(|&b| {
                if (0x20..0x7f).contains(&b) && b != b'\\' {
                    (b as char).to_string()
                } else {
                    format!("\\x{b:02x}")
                }
            })
            .collect()
    }

    /// The exact bytes of one frame of each kind. If this test fails, the wire format changed:
    /// bump `PROTOCOL_VERSION` and update PROTOCOL.md instead of editing the snapshot.
    #[test]
    fn golden_bytes_of_each_frame_kind_are_unchanged() {
        let expected = [
            r#"TRHB\x00\x01\x01\x00\x00\x00\x00\xc6{"protocol_version":1,"station_id":"station-01","patient_id":"p-0042","session_id":"2026-11-21T09-30-00Z","exercise":"sine-road","started_unix_ms":1795253400000,"software_version":"telerehab 0.1.0"}"#,
            r#"TRHB\x00\x01\x02\x00\x00\x00\x01${"session_id":"2026-11-21T09-30-00Z","seq":7,"t_s":0.7000000000000001,"exercise":"sine-road","speed_m_s":12.5,"lateral_m":-0.25,"rms_lateral_m":0.31,"max_lateral_m":0.9,"pct_in_lane":97.5,"max_abs_torque_nm":1.2,"loop_p99_us":45.0,"ticks":700,"dropped_records":0,"extra":{"assist_level":0.5}}"#,
            r#"TRHB\x00\x01\x03\x00\x00\x00\x00-{"session_id":"2026-11-21T09-30-00Z","seq":7}"#,
            r#"TRHB\x00\x01\x04\x00\x00\x00\x00:{"id":"reg-3","toml":"[exercise]\x5cnname = \x5c"sine-road\x5c"\x5cn"}"#,
            r#"TRHB\x00\x01\x05\x00\x00\x00\x00O{"session_id":"2026-11-21T09-30-00Z","reason":"session complete","final_seq":7}"#,
            r#"TRHB\x00\x01\x06\x00\x00\x00\x00\x17{"message":"bad magic"}"#,
        ];
        for (frame, want) in one_of_each().iter().zip(expected) {
            let bytes = encode_to_vec(frame).unwrap();
            assert_eq!(escape(&bytes), want, "{} frame bytes changed", frame.kind());
        }
    }

    /// A Paired frame from an older hub (no pseudonym) keeps its bytes; the pseudonym is one
    /// field more at the end, and an older station's reading of it is the frame it knew.
    #[test]
    fn golden_bytes_of_paired_with_and_without_the_pseudonym() {
        let mut paired = crate::frame::Paired {
            station_id: "st-1".into(),
            patient_id: "p-0042".into(),
            ca_pem: "CA".into(),
            cert_pem: "CERT".into(),
            server_name: "hub.clinic".into(),
            mac: "ab".repeat(32),
            patient_pseudonym: None,
        };
        let old = encode_to_vec(&Frame::Paired(paired.clone())).unwrap();
        assert_eq!(escape(&old), PAIRED_OLD_GOLDEN);
        paired.patient_pseudonym = Some("P-0042".into());
        let new = encode_to_vec(&Frame::Paired(paired.clone())).unwrap();
        assert_eq!(escape(&new), PAIRED_NEW_GOLDEN);
        assert_eq!(
            decode(&new).unwrap().unwrap().0,
            Frame::Paired(paired.clone())
        );
        paired.patient_pseudonym = Some("P\n1".into());
        assert!(
            encode_to_vec(&Frame::Paired(paired)).is_err(),
            "control characters in the pseudonym are refused"
        );
    }

    /// Fields added after the first release are absent when unset (the bytes above hold), and
    /// pinned here when set.
    #[test]
    fn golden_bytes_of_version_range_error_code_and_measures() {
        let mut h = hello();
        h.min_protocol_version = Some(1);
        let bytes = encode_to_vec(&Frame::Hello(h)).unwrap();
        assert_eq!(
            escape(&bytes),
            r#"TRHB\x00\x01\x01\x00\x00\x00\x00\xdf{"protocol_version":1,"station_id":"station-01","patient_id":"p-0042","session_id":"2026-11-21T09-30-00Z","exercise":"sine-road","started_unix_ms":1795253400000,"software_version":"telerehab 0.1.0","min_protocol_version":1}"#
        );
        let e = Frame::Error(ErrorFrame {
            message: "update required".into(),
            code: Some(crate::frame::UPDATE_REQUIRED.into()),
        });
        assert_eq!(
            escape(&encode_to_vec(&e).unwrap()),
            r#"TRHB\x00\x01\x06\x00\x00\x00\x006{"message":"update required","code":"update_required"}"#
        );
        let bye = Frame::Bye(Bye {
            session_id: "s1".into(),
            reason: "session complete".into(),
            final_seq: Some(7),
            measures: [("sparc_median".to_owned(), -1.5)].into(),
            hub_unix_ms: None,
            checkin: None,
            difficulty: None,
            exercises: Vec::new(),
        });
        let bytes = encode_to_vec(&bye).unwrap();
        assert_eq!(
            escape(&bytes),
            r#"TRHB\x00\x01\x05\x00\x00\x00\x00^{"session_id":"s1","reason":"session complete","final_seq":7,"measures":{"sparc_median":-1.5}}"#
        );
        assert_eq!(decode(&bytes).unwrap().unwrap().0, bye);
        let mut nan = bye;
        if let Frame::Bye(b) = &mut nan {
            b.measures.insert("ldlj_median".into(), f64::NAN);
        }
        assert!(encode_to_vec(&nan).is_err(), "a NaN measure is refused");
        // The hub's reply with its clock: one field more at the end, nothing else changed.
        let stored = Frame::Bye(Bye {
            session_id: "s1".into(),
            reason: "stored".into(),
            final_seq: None,
            measures: Default::default(),
            hub_unix_ms: Some(1_795_253_400_123),
            checkin: None,
            difficulty: None,
            exercises: Vec::new(),
        });
        let bytes = encode_to_vec(&stored).unwrap();
        assert_eq!(
            escape(&bytes),
            r#"TRHB\x00\x01\x05\x00\x00\x00\x00R{"session_id":"s1","reason":"stored","final_seq":null,"hub_unix_ms":1795253400123}"#
        );
        assert_eq!(decode(&bytes).unwrap().unwrap().0, stored);
    }

    /// The Hello's optional wheel (absent above when unset), pinned when set; an older
    /// hub's reading ignores it, and a Hello without it still decodes.
    #[test]
    fn golden_bytes_of_a_hello_with_its_wheel() {
        let mut h = hello();
        h.wheel = Some(crate::frame::WheelInfo {
            model: "Logitech G29".into(),
            rated_torque_nm: 2.2,
            ceiling_nm: 1.87,
            unknown: false,
        });
        let frame = Frame::Hello(h);
        let bytes = encode_to_vec(&frame).unwrap();
        assert_eq!(
            escape(&bytes),
            r#"TRHB\x00\x01\x01\x00\x00\x00\x01\x0f{"protocol_version":1,"station_id":"station-01","patient_id":"p-0042","session_id":"2026-11-21T09-30-00Z","exercise":"sine-road","started_unix_ms":1795253400000,"software_version":"telerehab 0.1.0","wheel":{"model":"Logitech G29","rated_torque_nm":2.2,"ceiling_nm":1.87}}"#
        );
        assert_eq!(decode(&bytes).unwrap().unwrap().0, frame);
    }

    #[test]
    fn a_hello_whose_wheel_ceiling_is_above_its_rating_is_refused_naming_the_field() {
        let mut h = hello();
        h.wheel = Some(crate::frame::WheelInfo {
            model: "unknown wheel 1234:5678".into(),
            rated_torque_nm: 5.0,
            ceiling_nm: 6.0,
            unknown: true,
        });
        let err = h.validate().unwrap_err().0;
        assert!(err.contains("wheel.ceiling_nm"), "{err}");
        h.wheel.as_mut().unwrap().ceiling_nm = 3.0;
        assert!(h.validate().is_ok());
    }

    /// The regimen's optional prescriber (absent in the frames above when unset), pinned when
    /// set; a prescriber with a control character is refused naming the field.
    #[test]
    fn golden_bytes_of_a_regimen_with_its_prescriber() {
        let frame = Frame::Regimen(Regimen {
            id: "p-0042-v3".into(),
            toml: "[[exercise]]\nkind = \"sine\"\n".into(),
            prescribed_by: Some("ana@clinic.example".into()),
        });
        let bytes = encode_to_vec(&frame).unwrap();
        assert_eq!(
            escape(&bytes),
            r#"TRHB\x00\x01\x04\x00\x00\x00\x00`{"id":"p-0042-v3","toml":"[[exercise]]\x5cnkind = \x5c"sine\x5c"\x5cn","prescribed_by":"ana@clinic.example"}"#
        );
        assert_eq!(decode(&bytes).unwrap().unwrap().0, frame);
        let Frame::Regimen(mut bad) = frame else {
            unreachable!()
        };
        bad.prescribed_by = Some("ana\u{7}@clinic.example".into());
        let err = Frame::Regimen(bad).validate().unwrap_err().0;
        assert!(err.contains("prescribed_by"), "{err}");
    }

    /// Version 2's frames (the therapist's messages), pinned; text counted in characters.
    #[test]
    fn golden_bytes_of_message_and_message_seen() {
        let message = Frame::Message(crate::frame::Message {
            id: "m-0123456789abcdef".into(),
            text: "Bien joué — à jeudi".into(),
            sent_unix_ms: 1_795_253_400_000,
        });
        let bytes = encode_to_vec(&message).unwrap();
        assert_eq!(
            escape(&bytes),
            r#"TRHB\x00\x01\x0e\x00\x00\x00\x00Y{"id":"m-0123456789abcdef","text":"Bien jou\xc3\xa9 \xe2\x80\x94 \xc3\xa0 jeudi","sent_unix_ms":1795253400000}"#
        );
        assert_eq!(decode(&bytes).unwrap().unwrap().0, message);
        let seen = Frame::MessageSeen(crate::frame::MessageSeen {
            id: "m-0123456789abcdef".into(),
            seen_unix_ms: 1_795_253_401_000,
        });
        let bytes = encode_to_vec(&seen).unwrap();
        assert_eq!(
            escape(&bytes),
            r#"TRHB\x00\x01\x0f\x00\x00\x00\x008{"id":"m-0123456789abcdef","seen_unix_ms":1795253401000}"#
        );
        assert_eq!(decode(&bytes).unwrap().unwrap().0, seen);
    }

    #[test]
    fn a_care_frame_carries_the_pain_threshold_phone_and_clearance_and_refuses_bad_ones() {
        let care = crate::frame::Care {
            pain_threshold_0_10: 7,
            clinic_phone: Some("+49 30 1234567".into()),
            cleared_unix_ms: Some(1_795_253_400_000),
        };
        let bytes = encode_to_vec(&Frame::Care(care.clone())).unwrap();
        assert_eq!(bytes[6], 16, "the Care kind byte");
        assert_eq!(
            decode(&bytes).unwrap().unwrap().0,
            Frame::Care(care.clone())
        );
        // A hub that set no phone and never cleared sends only the threshold.
        let bare = crate::frame::Care {
            clinic_phone: None,
            cleared_unix_ms: None,
            ..care.clone()
        };
        let bytes = encode_to_vec(&Frame::Care(bare)).unwrap();
        assert!(escape(&bytes).ends_with(r#"{"pain_threshold_0_10":7}"#));
        for (bad, names) in [
            (
                crate::frame::Care {
                    pain_threshold_0_10: 11,
                    ..care.clone()
                },
                "pain_threshold_0_10",
            ),
            (
                crate::frame::Care {
                    pain_threshold_0_10: 0,
                    ..care.clone()
                },
                "pain_threshold_0_10",
            ),
            (
                crate::frame::Care {
                    clinic_phone: Some("call me\u{1b}".into()),
                    ..care.clone()
                },
                "phone number contains",
            ),
        ] {
            let e = Frame::Care(bad).validate().unwrap_err();
            assert!(e.to_string().contains(names), "{e}");
        }
    }

    #[test]
    fn a_message_frame_with_a_bad_text_or_id_is_refused_naming_the_problem() {
        let frame = |id: &str, text: String| {
            Frame::Message(crate::frame::Message {
                id: id.into(),
                text,
                sent_unix_ms: 0,
            })
        };
        assert!(encode_to_vec(&frame("m-1", "é".repeat(500))).is_ok());
        for (id, text, why) in [
            ("m-1", "a".repeat(501), "too long: 501 characters"),
            ("m-1", " ".into(), "empty"),
            ("m-1", "two\nlines".into(), "control character"),
            ("../m", "hi".into(), "id"),
        ] {
            let err = encode_to_vec(&frame(id, text)).unwrap_err().to_string();
            assert!(err.contains(why), "{err:?} does not say {why:?}");
        }
        // A hostile peer's bytes are refused on decode too.
        let mut bytes = encode_to_vec(&frame("m-1", "ok".into())).unwrap();
        let at = bytes.windows(2).position(|w| w == b"ok").unwrap();
        bytes[at] = 0x07;
        let err = decode(&bytes).unwrap_err().to_string();
        assert!(err.contains("control character"), "{err}");
    }

    #[test]
    fn every_frame_kind_round_trips() {
        for frame in one_of_each() {
            let bytes = encode_to_vec(&frame).unwrap();
            let (back, used) = decode(&bytes).unwrap().unwrap();
            assert_eq!(used, bytes.len());
            assert_eq!(back, frame);
        }
    }

    #[test]
    fn every_strict_prefix_is_incomplete_not_an_error() {
        let bytes = encode_to_vec(&Frame::Hello(hello())).unwrap();
        for n in 0..bytes.len() {
            assert!(decode(&bytes[..n]).unwrap().is_none(), "prefix {n}");
        }
    }

    #[test]
    fn bad_magic_is_reported_from_the_first_byte() {
        let err = decode(b"G").unwrap_err();
        assert!(matches!(err, CodecError::BadMagic { .. }), "{err}");
        let err = decode(b"GET / HTTP/1.1\r\n").unwrap_err();
        assert!(err.to_string().contains("bad magic"), "{err}");
    }

    #[test]
    fn header_errors_are_distinguished() {
        let mut bytes = encode_to_vec(&Frame::Hello(hello())).unwrap();
        bytes[5] = 2;
        assert!(matches!(
            decode(&bytes),
            Err(CodecError::UnsupportedVersion {
                found: 2,
                supported: 1
            })
        ));
        bytes[5] = 1;
        bytes[6] = 99;
        assert!(matches!(decode(&bytes), Err(CodecError::UnknownKind(99))));
        bytes[6] = 1;
        bytes[7] = 0x80;
        assert!(matches!(
            decode(&bytes),
            Err(CodecError::ReservedFlags(0x80))
        ));
    }

    #[test]
    fn oversize_length_is_rejected_before_its_payload_arrives() {
        let mut header = b"TRHB\x00\x01\x02\x00".to_vec();
        header.extend_from_slice(&((MAX_PAYLOAD_LEN as u32) + 1).to_be_bytes());
        assert!(matches!(
            decode(&header),
            Err(CodecError::Oversize { len, .. }) if len == MAX_PAYLOAD_LEN + 1
        ));
    }

    #[test]
    fn oversize_frame_is_not_encoded_and_leaves_buffer_untouched() {
        let frame = Frame::Regimen(Regimen {
            id: "big".into(),
            toml: "x".repeat(MAX_PAYLOAD_LEN),
            prescribed_by: None,
        });
        let mut out = b"keep".to_vec();
        assert!(matches!(
            encode(&frame, &mut out),
            Err(CodecError::Oversize { .. })
        ));
        assert_eq!(out, b"keep");
    }

    #[test]
    fn bad_json_and_invalid_fields_name_the_problem() {
        let mut bytes = b"TRHB\x00\x01\x03\x00".to_vec();
        let payload = br#"{"session_id":"s","seq":"seven"}"#;
        bytes.extend_from_slice(&(payload.len() as u32).to_be_bytes());
        bytes.extend_from_slice(payload);
        let err = decode(&bytes).unwrap_err();
        assert!(
            matches!(
                err,
                CodecError::BadJson {
                    kind: FrameKind::Ack,
                    ..
                }
            ),
            "{err}"
        );

        let mut bytes = b"TRHB\x00\x01\x03\x00".to_vec();
        let payload = br#"{"session_id":"../../etc","seq":1}"#;
        bytes.extend_from_slice(&(payload.len() as u32).to_be_bytes());
        bytes.extend_from_slice(payload);
        let err = decode(&bytes).unwrap_err().to_string();
        assert!(err.contains("session_id"), "{err}");
    }

    #[test]
    fn invalid_summary_is_refused_by_the_encoder() {
        let mut s = summary("s", 1);
        s.t_s = f64::NAN;
        let err = encode_to_vec(&Frame::Summary(s)).unwrap_err().to_string();
        assert!(err.contains("t_s"), "{err}");
    }

    #[test]
    fn decoder_returns_frames_fed_one_byte_at_a_time() {
        let frames = one_of_each();
        let mut bytes = Vec::new();
        for f in &frames {
            encode(f, &mut bytes).unwrap();
        }
        let mut dec = FrameDecoder::new();
        let mut got = Vec::new();
        for b in &bytes {
            dec.extend(std::slice::from_ref(b));
            while let Some(f) = dec.next_frame().unwrap() {
                got.push(f);
            }
        }
        assert_eq!(got, frames);
        assert_eq!(dec.buffered_len(), 0);
    }

    fn finite() -> impl Strategy<Value = f64> {
        -1e6..1e6f64
    }

    prop_compose! {
        fn arb_summary()(
            seq in any::<u64>(),
            t_s in 0.0..1e6f64,
            speed in finite(), lat in finite(),
            rms in 0.0..1e3f64, max in 0.0..1e3f64, pct in 0.0..=100.0f64,
            torque in 0.0..10.0f64, p99 in 0.0..1e6f64,
            ticks in any::<u64>(), dropped in any::<u64>(),
            extra in proptest::collection::btree_map("[a-z_]{1,16}", finite(), 0..8),
            session in "[A-Za-z0-9_-][A-Za-z0-9_.-]{0,63}",
        ) -> Summary {
            Summary {
                session_id: session, seq, t_s, exercise: "sine-road".into(),
                speed_m_s: speed, lateral_m: lat, rms_lateral_m: rms, max_lateral_m: max,
                pct_in_lane: pct, max_abs_torque_nm: torque, loop_p99_us: p99,
                ticks, dropped_records: dropped, extra,
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 256, rng_seed: proptest::test_runner::RngSeed::Fixed(7), ..ProptestConfig::default() })]

        #[test]
        fn summary_round_trips_exactly(s in arb_summary()) {
            let frame = Frame::Summary(s);
            let bytes = encode_to_vec(&frame).unwrap();
            let (back, used) = decode(&bytes).unwrap().unwrap();
            prop_assert_eq!(used, bytes.len());
            prop_assert_eq!(back, frame);
        }

        #[test]
        fn random_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..512)) {
            let mut dec = FrameDecoder::new();
            dec.extend(&bytes);
            for _ in 0..4 {
                match dec.next_frame() {
                    Ok(Some(_)) => {}
                    Ok(None) | Err(_) => break,
                }
            }
        }

        #[test]
        fn corrupted_valid_frame_never_panics(
            s in arb_summary(), pos in any::<proptest::sample::Index>(), byte in any::<u8>(),
        ) {
            let mut bytes = encode_to_vec(&Frame::Summary(s)).unwrap();
            let i = pos.index(bytes.len());
            bytes[i] = byte;
            let _ = decode(&bytes);
        }

        #[test]
        fn random_payload_behind_valid_header_never_panics(
            kind in 1u8..=13, payload in proptest::collection::vec(any::<u8>(), 0..256),
        ) {
            let mut bytes = b"TRHB\x00\x01".to_vec();
            bytes.push(kind);
            bytes.push(0);
            bytes.extend_from_slice(&(payload.len() as u32).to_be_bytes());
            bytes.extend_from_slice(&payload);
            prop_assert!(decode(&bytes).is_err());
        }
    }

    /// A station's Bye with the patient's check-in: the answers at the end, each optional; an
    /// older hub ignores the field, and an answer out of range is refused.
    #[test]
    fn golden_bytes_of_a_bye_with_a_checkin_and_its_ranges() {
        let bye = Frame::Bye(Bye {
            session_id: "s1".into(),
            reason: "session complete".into(),
            final_seq: Some(7),
            measures: Default::default(),
            hub_unix_ms: None,
            checkin: Some(crate::frame::CheckIn {
                pain_0_10: Some(3),
                tiredness_0_10: None,
                difficulty: Some("about_right".into()),
            }),
            difficulty: None,
            exercises: Vec::new(),
        });
        let bytes = encode_to_vec(&bye).unwrap();
        assert_eq!(
            escape(&bytes),
            r#"TRHB\x00\x01\x05\x00\x00\x00\x00r{"session_id":"s1","reason":"session complete","final_seq":7,"checkin":{"pain_0_10":3,"difficulty":"about_right"}}"#
        );
        assert_eq!(decode(&bytes).unwrap().unwrap().0, bye);
        for (pain, difficulty) in [(11, "about_right"), (3, "boring")] {
            let mut bad = bye.clone();
            if let Frame::Bye(b) = &mut bad {
                b.checkin = Some(crate::frame::CheckIn {
                    pain_0_10: Some(pain),
                    tiredness_0_10: None,
                    difficulty: Some(difficulty.into()),
                });
            }
            let err = bad.validate().unwrap_err().0;
            assert!(err.contains("checkin."), "{err}");
        }
    }

    /// A station's Bye with each exercise's results: index, kind, the patient's name for it,
    /// prescribed and active time, scores with units in their names; an older hub ignores the
    /// field, an older station's Bye reads as none, and a result out of bounds is refused.
    #[test]
    fn golden_bytes_of_a_bye_with_exercise_results_and_their_bounds() {
        use crate::frame::{ExerciseResult, MAX_EXERCISE_RESULTS};
        use std::collections::BTreeMap;
        let result = ExerciseResult {
            index: 1,
            kind: "dial-sine".into(),
            name: "Dial sine".into(),
            prescribed_s: 45.0,
            active_s: 44.5,
            scores: BTreeMap::from([("dial_mean_abs_error_deg".to_owned(), 3.25)]),
            assessment: None,
        };
        let bye = Frame::Bye(Bye {
            session_id: "s1".into(),
            reason: "complete".into(),
            final_seq: Some(7),
            measures: Default::default(),
            hub_unix_ms: None,
            checkin: None,
            exercises: vec![result.clone()],
            difficulty: None,
        });
        let bytes = encode_to_vec(&bye).unwrap();
        assert_eq!(
            escape(&bytes),
            r#"TRHB\x00\x01\x05\x00\x00\x00\x00\xc3{"session_id":"s1","reason":"complete","final_seq":7,"exercises":[{"index":1,"kind":"dial-sine","name":"Dial sine","prescribed_s":45.0,"active_s":44.5,"scores":{"dial_mean_abs_error_deg":3.25}}]}"#
        );
        assert_eq!(decode(&bytes).unwrap().unwrap().0, bye);
        let older = br#"{"session_id":"s1","reason":"complete","final_seq":7}"#;
        let mut framed = b"TRHB\x00\x01\x05\x00".to_vec();
        framed.extend_from_slice(&(older.len() as u32).to_be_bytes());
        framed.extend_from_slice(older);
        let Frame::Bye(b) = decode(&framed).unwrap().unwrap().0 else {
            panic!("not a Bye")
        };
        assert!(b.exercises.is_empty());
        let refused = |edit: &dyn Fn(&mut Vec<ExerciseResult>)| {
            let mut bad = bye.clone();
            if let Frame::Bye(b) = &mut bad {
                edit(&mut b.exercises);
            }
            bad.validate().unwrap_err().0
        };
        let err = refused(&|e| e[0].active_s = f64::NAN);
        assert!(err.contains("exercises[1].active_s"), "{err}");
        let err = refused(&|e| e[0].kind = "../x".into());
        assert!(err.contains("exercises[1].kind"), "{err}");
        let err = refused(&|e| {
            e[0].scores.insert("x_deg".into(), f64::INFINITY);
        });
        assert!(err.contains("exercises[1].scores"), "{err}");
        let err = refused(&|e| e.push(e[0].clone()));
        assert!(err.contains("twice"), "{err}");
        let err = refused(&|e| {
            *e = (0..=MAX_EXERCISE_RESULTS as u32)
                .map(|index| ExerciseResult {
                    index,
                    ..e[0].clone()
                })
                .collect()
        });
        assert!(err.contains("at most 60"), "{err}");
    }

    /// An assessment's results say so in an optional field: an exercise's JSON has none (so
    /// older hubs and the golden bytes above are unchanged), an assessment's round-trips, and
    /// the tag on an exercise that is no assessment, or of protocol 0, is refused.
    #[test]
    fn an_assessment_part_is_tagged_with_its_protocol_and_seed_and_only_it() {
        use crate::frame::{AssessmentTag, ExerciseResult};
        let part = ExerciseResult {
            index: 0,
            kind: "assessment-steps".into(),
            name: "Assessment steps".into(),
            prescribed_s: 60.0,
            active_s: 60.0,
            scores: Default::default(),
            assessment: Some(AssessmentTag {
                protocol: 1,
                seed: 77,
            }),
        };
        let exercise = ExerciseResult {
            kind: "dial-sine".into(),
            assessment: None,
            index: 1,
            ..part.clone()
        };
        assert!(
            !serde_json::to_string(&exercise)
                .unwrap()
                .contains("assessment")
        );
        let frame = bye_of(vec![part.clone(), exercise.clone()]);
        let bytes = encode_to_vec(&frame).unwrap();
        assert_eq!(decode(&bytes).unwrap().map(|(f, _)| f), Some(frame));
        let json = serde_json::to_string(&part).unwrap();
        assert!(
            json.contains(r#""assessment":{"protocol":1,"seed":77}"#),
            "{json}"
        );
        let mislabelled = ExerciseResult {
            assessment: part.assessment,
            ..exercise
        };
        let err = bye_of(vec![mislabelled])
            .validate()
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("assessment") && err.contains("dial-sine"),
            "{err}"
        );
        let zero = ExerciseResult {
            assessment: Some(AssessmentTag {
                protocol: 0,
                seed: 1,
            }),
            ..part
        };
        let err = bye_of(vec![zero]).validate().unwrap_err().to_string();
        assert!(err.contains("protocol"), "{err}");
    }

    /// A complete session's Bye carrying `exercises`.
    fn bye_of(exercises: Vec<crate::frame::ExerciseResult>) -> Frame {
        Frame::Bye(Bye {
            session_id: "s1".into(),
            reason: "complete".into(),
            final_seq: Some(7),
            measures: Default::default(),
            hub_unix_ms: None,
            checkin: None,
            exercises,
            difficulty: None,
        })
    }

    /// One session runs one assessment: a hostile or broken station's Bye with a part twice
    /// or parts of two assessments is refused, naming the part (the hub would file them as
    /// one assessment and export a bundle with two resources of one identifier).
    #[test]
    fn a_bye_with_an_assessment_part_twice_or_two_assessments_is_refused() {
        use crate::frame::{AssessmentTag, ExerciseResult};
        let part = |index, kind: &str, seed| ExerciseResult {
            index,
            kind: kind.into(),
            name: "Assessment".into(),
            prescribed_s: 60.0,
            active_s: 60.0,
            scores: Default::default(),
            assessment: Some(AssessmentTag { protocol: 1, seed }),
        };
        let one = vec![
            part(0, "assessment-range", 5),
            part(1, "assessment-steps", 5),
        ];
        assert!(bye_of(one).validate().is_ok());
        let twice = vec![
            part(0, "assessment-steps", 5),
            part(1, "assessment-steps", 5),
        ];
        let err = bye_of(twice).validate().unwrap_err().to_string();
        assert!(
            err.contains("exercises[1]") && err.contains("second"),
            "{err}"
        );
        let two = vec![
            part(0, "assessment-range", 5),
            part(1, "assessment-steps", 6),
        ];
        let err = bye_of(two).validate().unwrap_err().to_string();
        assert!(
            err.contains("exercises[1]") && err.contains("one assessment"),
            "{err}"
        );
    }

    /// A station's Bye with the difficulty its session ran at: additive, an older hub ignores
    /// it, and a value out of range or a reason with control characters is refused.
    #[test]
    fn a_difficultys_why_travels_beside_its_words_and_is_checked() {
        let why = crate::frame::DifficultyWhy {
            code: "success-above".into(),
            success_pct: Some(82.0),
            target_pct: Some(70.0),
            held_at: Some("highest".into()),
        };
        let change = crate::frame::DifficultyChange {
            difficulty: 0.8,
            change: 0.0,
            reason: "success 82 % above the 70 % target: +0.05; held at the therapist's \
                     highest (0.80)"
                .into(),
            success_rate: Some(0.82),
            why: Some(why.clone()),
        };
        let json = serde_json::to_value(&change).unwrap();
        assert_eq!(
            json["why"],
            serde_json::json!({"code": "success-above", "success_pct": 82.0, "target_pct": 70.0, "held_at": "highest"})
        );
        assert_eq!(
            serde_json::from_value::<crate::frame::DifficultyChange>(json).unwrap(),
            change
        );
        assert!(change.validate().is_ok());
        for bad in [
            crate::frame::DifficultyWhy {
                code: "because".into(),
                ..why.clone()
            },
            crate::frame::DifficultyWhy {
                success_pct: Some(f64::NAN),
                ..why.clone()
            },
            crate::frame::DifficultyWhy {
                held_at: Some("middle".into()),
                ..why.clone()
            },
        ] {
            let mut c = change.clone();
            c.why = Some(bad);
            let err = c.validate().unwrap_err().0;
            assert!(err.contains("difficulty.why."), "{err}");
        }
    }

    #[test]
    fn golden_bytes_of_a_bye_with_a_difficulty_and_its_ranges() {
        let bye = Frame::Bye(Bye {
            session_id: "s1".into(),
            reason: "session complete".into(),
            final_seq: Some(7),
            measures: Default::default(),
            hub_unix_ms: None,
            checkin: None,
            difficulty: Some(crate::frame::DifficultyChange {
                difficulty: 0.55,
                change: 0.05,
                reason: "success 82 % above the 70 % target: +0.05".into(),
                success_rate: Some(0.75),
                why: None,
            }),
            exercises: Vec::new(),
        });
        let bytes = encode_to_vec(&bye).unwrap();
        assert_eq!(
            escape(&bytes),
            r#"TRHB\x00\x01\x05\x00\x00\x00\x00\xb5{"session_id":"s1","reason":"session complete","final_seq":7,"difficulty":{"difficulty":0.55,"change":0.05,"reason":"success 82 % above the 70 % target: +0.05","success_rate":0.75}}"#
        );
        assert_eq!(decode(&bytes).unwrap().unwrap().0, bye);
        let older: serde_json::Value = serde_json::from_str(
            r#"{"session_id":"s1","reason":"session complete","final_seq":7}"#,
        )
        .unwrap();
        let read: Bye = serde_json::from_value(older).unwrap();
        assert_eq!(read.difficulty, None);
        for (d, change, reason) in [(1.2, 0.0, "ok"), (0.5, f64::NAN, "ok"), (0.5, 0.0, "a\nb")] {
            let mut bad = bye.clone();
            if let Frame::Bye(b) = &mut bad {
                b.difficulty = Some(crate::frame::DifficultyChange {
                    difficulty: d,
                    change,
                    reason: reason.into(),
                    success_rate: None,
                    why: None,
                });
            }
            let err = bad.validate().unwrap_err().0;
            assert!(err.contains("difficulty."), "{err}");
        }
    }
}
