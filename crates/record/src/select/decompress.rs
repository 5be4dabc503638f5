//! The zstd decoder of the indexed reader's chunks, its window bounded as the walk's is
//! ([`crate::walk::ZSTD_WINDOW_LOG_MAX`]): mcap's own accepts zstd's default of 128 MiB.

use crate::walk::ZSTD_WINDOW_LOG_MAX;
use mcap::McapError;
use mcap::sans_io::decompressor::{DecompressResult, Decompressor};
use zstd::zstd_safe::{DParameter, DStream, InBuffer, OutBuffer, ResetDirective, get_error_name};

/// A zstd chunk decoder whose window is at most 2^[`ZSTD_WINDOW_LOG_MAX`] bytes.
#[derive(Default)]
pub(super) struct BoundedZstd {
    stream: Option<DStream<'static>>,
}

fn zstd_error(code: usize) -> McapError {
    McapError::DecompressionError(format!("zstd: {}", get_error_name(code)))
}

impl BoundedZstd {
    fn stream(&mut self) -> Result<&mut DStream<'static>, McapError> {
        if self.stream.is_none() {
            let mut stream = DStream::create();
            stream.init().map_err(zstd_error)?;
            stream
                .set_parameter(DParameter::WindowLogMax(ZSTD_WINDOW_LOG_MAX))
                .map_err(zstd_error)?;
            self.stream = Some(stream);
        }
        Ok(self.stream.as_mut().expect("made above"))
    }
}

impl Decompressor for BoundedZstd {
    fn next_read_size(&self) -> usize {
        0
    }

    fn decompress(&mut self, src: &[u8], dst: &mut [u8]) -> Result<DecompressResult, McapError> {
        let stream = self.stream()?;
        let mut input = InBuffer::around(src);
        let mut output = OutBuffer::around(dst);
        stream
            .decompress_stream(&mut output, &mut input)
            .map_err(zstd_error)?;
        Ok(DecompressResult {
            consumed: input.pos,
            wrote: output.pos(),
        })
    }

    fn reset(&mut self) -> Result<(), McapError> {
        if let Some(stream) = self.stream.as_mut() {
            // The session only: the window bound stays set.
            stream
                .reset(ResetDirective::SessionOnly)
                .map_err(zstd_error)?;
        }
        Ok(())
    }

    fn name(&self) -> &'static str {
        "zstd"
    }
}
