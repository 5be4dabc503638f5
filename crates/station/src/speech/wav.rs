//! The little of RIFF WAV that espeak-ng writes: 16-bit PCM, mono, its sample rate.

use super::SpeechError;
use regimen::NeglectedSide;

/// Decoded PCM sound.
#[derive(Debug, Clone, PartialEq)]
pub struct Wav {
    /// Samples a second, Hz.
    pub sample_rate: u32,
    /// Channels interleaved in `samples`.
    pub channels: u16,
    /// Samples in −1…1.
    pub samples: Vec<f32>,
}

fn u16_at(b: &[u8], i: usize) -> Option<u16> {
    Some(u16::from_le_bytes(b.get(i..i + 2)?.try_into().ok()?))
}

fn u32_at(b: &[u8], i: usize) -> Option<u32> {
    Some(u32::from_le_bytes(b.get(i..i + 4)?.try_into().ok()?))
}

impl Wav {
    /// Reads 16-bit PCM WAV bytes. A `data` chunk whose declared size runs past the end (a
    /// WAV written to a pipe) is read to the end.
    pub fn parse(b: &[u8]) -> Result<Wav, SpeechError> {
        let bad = |m: &str| SpeechError::BadWav(m.to_owned());
        if b.get(0..4) != Some(b"RIFF") || b.get(8..12) != Some(b"WAVE") {
            return Err(bad("not a RIFF WAVE"));
        }
        let (mut i, mut fmt) = (12, None);
        while i + 8 <= b.len() {
            let id = &b[i..i + 4];
            let len = u32_at(b, i + 4).ok_or_else(|| bad("truncated chunk"))? as usize;
            let body = i + 8;
            if id == b"fmt " {
                let format = u16_at(b, body).ok_or_else(|| bad("short fmt"))?;
                let channels = u16_at(b, body + 2).ok_or_else(|| bad("short fmt"))?;
                let rate = u32_at(b, body + 4).ok_or_else(|| bad("short fmt"))?;
                let bits = u16_at(b, body + 14).ok_or_else(|| bad("short fmt"))?;
                if format != 1 || bits != 16 || channels == 0 || rate == 0 {
                    return Err(bad("not 16-bit PCM"));
                }
                fmt = Some((channels, rate));
            } else if id == b"data" {
                let (channels, sample_rate) = fmt.ok_or_else(|| bad("data before fmt"))?;
                let end = body.saturating_add(len).min(b.len());
                let samples = b[body..end]
                    .chunks_exact(2)
                    .map(|s| f32::from(i16::from_le_bytes([s[0], s[1]])) / 32768.0)
                    .collect();
                return Ok(Wav {
                    sample_rate,
                    channels,
                    samples,
                });
            }
            i = body.saturating_add(len + (len & 1));
        }
        Err(bad("no data chunk"))
    }

    /// The sound as stereo (channels, interleaved samples): from both sides, or from one
    /// side only (the other at a sixth) for the anchoring cue.
    pub fn stereo_from(&self, side: NeglectedSide) -> (u16, Vec<f32>) {
        let (l, r) = match side {
            NeglectedSide::None => (1.0, 1.0),
            NeglectedSide::Left => (1.0, 0.15),
            NeglectedSide::Right => (0.15, 1.0),
        };
        let ch = usize::from(self.channels.max(1));
        let mono = self
            .samples
            .chunks(ch)
            .map(|f| f.iter().sum::<f32>() / f.len() as f32);
        (2, mono.flat_map(|m| [m * l, m * r]).collect())
    }
}
