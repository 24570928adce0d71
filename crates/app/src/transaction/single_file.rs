//! The output transaction of a command that writes one file
//! (`import --out`): the file is written whole under a temporary name
//! beside its final one, flushed to disk, then renamed into place, so the
//! final name holds the old file or the whole new one, never a part.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use super::identity::Input;
use super::Begin;
use crate::Error;

/// Writes `contents` to `target` through a temporary file and a rename.
///
/// `target` must not be one of `begin.inputs` by any spelling (file
/// identity or canonical path, so a symbolic link to an input is the
/// input); an existing `target` is replaced only with `begin.force`, and a
/// symbolic link there is replaced itself, never written through.
///
/// ```
/// use kestrel_app::transaction::{publish_file, Begin};
/// let dir = std::env::temp_dir().join(format!("kestrel-doc-one-{}", std::process::id()));
/// std::fs::create_dir_all(&dir).unwrap();
/// let out = dir.join("a.toml");
/// publish_file(&out, b"x = 1\n", &Begin::command(["example"]))?;
/// assert!(publish_file(&out, b"x = 2\n", &Begin::command(["example"])).is_err());
/// let force = Begin { force: true, ..Begin::command(["example"]) };
/// publish_file(&out, b"x = 2\n", &force)?;
/// assert_eq!(std::fs::read_to_string(&out).unwrap(), "x = 2\n");
/// # std::fs::remove_dir_all(&dir).unwrap();
/// # Ok::<(), kestrel_app::Error>(())
/// ```
///
/// # Errors
/// [`Error::Failed`] when `target` is an input, a folder, or exists without
/// `force`; [`Error::Io`] / [`Error::DiskFull`] naming `target` when the
/// write fails (the temporary file is removed, `target` is unchanged).
pub fn publish_file(target: &Path, contents: &[u8], begin: &Begin) -> Result<PathBuf, Error> {
    let inputs: Vec<Input> = begin
        .inputs
        .iter()
        .map(|(flag, path)| Input::new(flag, path))
        .collect();
    if let Some(input) = inputs.iter().find(|i| i.is(target)) {
        return Err(Error::Failed(format!(
            "refusing to write {}: it is the {} input {}; choose another output",
            target.display(),
            input.flag,
            input.path.display()
        )));
    }
    let Some(name) = target.file_name() else {
        return Err(Error::Failed(format!(
            "{}: expected a file name to write",
            target.display()
        )));
    };
    match fs::symlink_metadata(target) {
        Ok(m) if m.is_dir() => {
            return Err(Error::Failed(format!(
                "{}: is a folder; expected a file name",
                target.display()
            )));
        }
        Ok(_) if !begin.force => {
            return Err(Error::Failed(format!(
                "refusing to replace {}: it exists (pass --force to replace it)",
                target.display()
            )));
        }
        _ => {}
    }
    let parent = match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let temp = Temp(parent.join(format!(
        ".kestrel-tmp-{}-{}-{}",
        name.to_string_lossy(),
        std::process::id(),
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos())
    )));
    // `create_new` refuses an existing name, a symbolic link included.
    let mut file = fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&temp.0)
        .map_err(|e| Error::io(target, e))?;
    file.write_all(contents)
        .and_then(|()| file.sync_all())
        .map_err(|e| Error::io(target, e))?;
    drop(file);
    fs::rename(&temp.0, target).map_err(|e| Error::io(target, e))?;
    std::mem::forget(temp);
    Ok(target.to_path_buf())
}

/// A temporary file, removed when dropped (an error on the way).
struct Temp(PathBuf);

impl Drop for Temp {
    fn drop(&mut self) {
        let _ = fs::remove_file(&self.0);
    }
}
