//! The `disk-full` fault: a recording's file whose disk fills up at the fault's session time.

/// A recording's file that fails every write with ENOSPC once its disk is [`Disk::fill`]ed,
/// as a full disk does (the station's recorder fills it at the injected fault's session time).
pub struct FillingFile {
    file: std::fs::File,
    full: Disk,
}

/// The disk under a [`FillingFile`]: filling it makes the file's writes fail; it also keeps
/// the last I/O error the file met (real or injected), which the MCAP library's own error
/// does not carry.
#[derive(Clone, Debug, Default)]
pub struct Disk {
    full: std::sync::Arc<std::sync::atomic::AtomicBool>,
    last_error: std::sync::Arc<std::sync::Mutex<Option<(std::io::ErrorKind, String)>>>,
}

impl Disk {
    /// From now on, writes fail.
    pub fn fill(&self) {
        self.full.store(true, std::sync::atomic::Ordering::Relaxed);
    }

    fn is_full(&self) -> bool {
        self.full.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// The last I/O error of the file, if any.
    pub fn last_error(&self) -> Option<std::io::Error> {
        let last = self.last_error.lock().ok()?.clone();
        last.map(|(kind, message)| std::io::Error::new(kind, message))
    }

    /// Keep `result`'s error, if it is one.
    fn note<T>(&self, result: std::io::Result<T>) -> std::io::Result<T> {
        if let (Err(e), Ok(mut slot)) = (&result, self.last_error.lock()) {
            *slot = Some((e.kind(), e.to_string()));
        }
        result
    }
}

impl FillingFile {
    /// `file` on `disk`.
    pub fn new(file: std::fs::File, disk: Disk) -> Self {
        Self { file, full: disk }
    }

    /// The file.
    pub fn file(&self) -> &std::fs::File {
        &self.file
    }
}

impl std::io::Write for FillingFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let result = if self.full.is_full() {
            Err(std::io::Error::from(std::io::ErrorKind::StorageFull))
        } else {
            self.file.write(buf)
        };
        self.full.note(result)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        let result = if self.full.is_full() {
            Err(std::io::Error::from(std::io::ErrorKind::StorageFull))
        } else {
            self.file.flush()
        };
        self.full.note(result)
    }
}

impl std::io::Seek for FillingFile {
    fn seek(&mut self, pos: std::io::SeekFrom) -> std::io::Result<u64> {
        let result = self.file.seek(pos);
        self.full.note(result)
    }
}
