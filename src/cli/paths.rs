//! Input: the files a command reads and the files it is asked to write.
//! Output: a refusal, before any work, when an output would replace one of
//! them.
//!
//! `wmslice slice part.stl -o part.stl` would otherwise slice the part and
//! then rename the result over it: the mesh lost, exit 0. The same for
//! a levels file, and for two outputs of one command (`-o r.json
//! --certificate r.json` keeps only the certificate).

use super::{usage, Failure};
use std::path::{Path, PathBuf};

/// A path the command reads or writes, and the option that named it.
pub struct Named<'a> {
    /// How the user named it: `"the mesh"`, `"-o"`, `"--levels-file"`.
    pub role: &'a str,
    /// The path as given.
    pub path: &'a Path,
}

/// Refuses (bad arguments) when an output names one of the inputs or
/// another output. Only regular files count, and outputs not yet
/// written: a device such as `/dev/null` or a terminal may be named twice
/// (`-o /dev/stdout` beside a mesh read from `/dev/stdin`), `-` is standard
/// input or output, and a name that is not a file (a built-in dataset) is
/// not read from disk.
pub fn refuse_overwriting(inputs: &[Named<'_>], outputs: &[Named<'_>]) -> Result<(), Failure> {
    for (k, out) in outputs.iter().enumerate() {
        let same = |o: &&Named<'_>| same_regular_file(o.path, out.path);
        // An input that is not a file on disk is not read from it.
        let read = inputs.iter().filter(|i| i.path.is_file()).find(same);
        let clash = read
            .map(|i| (i, "writing it would replace what is being read"))
            .or_else(|| {
                let earlier = outputs[..k].iter().find(same);
                earlier.map(|o| (o, "one output would replace the other"))
            });
        if let Some((other, what)) = clash {
            return Err(usage(format!(
                "{} {} names the same file as {} ({}): {what}; choose another path",
                out.role,
                out.path.display(),
                other.role,
                other.path.display(),
            )));
        }
    }
    Ok(())
}

/// Whether `a` and `b` are one regular file, or would be once written: the
/// same file by device and inode when both exist (hard and symbolic links
/// included), else the same place once the directories are resolved.
fn same_regular_file(a: &Path, b: &Path) -> bool {
    if a == Path::new("-") || b == Path::new("-") {
        return false;
    }
    let regular_or_absent = |p: &Path| std::fs::metadata(p).map_or(true, |m| m.is_file());
    if !regular_or_absent(a) || !regular_or_absent(b) {
        return false;
    }
    same_file::is_same_file(a, b).unwrap_or(false)
        || matches!((place(a), place(b)), (Some(x), Some(y)) if x == y)
}

/// Where `p` is or would be created: its directory resolved (symbolic
/// links, `.` and `..`) and its file name.
fn place(p: &Path) -> Option<PathBuf> {
    if let Ok(c) = p.canonicalize() {
        return Some(c);
    }
    let name = p.file_name()?;
    let dir = match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    Some(dir.canonicalize().ok()?.join(name))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn named<'a>(role: &'a str, path: &'a Path) -> Named<'a> {
        Named { role, path }
    }

    #[test]
    fn an_output_naming_an_input_or_another_output_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let mesh = dir.path().join("part.stl");
        std::fs::write(&mesh, b"solid\nendsolid\n").unwrap();
        let inputs = [named("the mesh", &mesh)];
        // The mesh itself, spelled another way.
        let dotted = dir.path().join(".").join("part.stl");
        let e = refuse_overwriting(&inputs, &[named("-o", &dotted)]).unwrap_err();
        assert_eq!(e.code, super::super::ExitCode::Usage);
        assert!(e.to_string().contains("the mesh"), "{e}");
        // A hard link to it.
        let link = dir.path().join("link.stl");
        std::fs::hard_link(&mesh, &link).unwrap();
        assert!(refuse_overwriting(&inputs, &[named("-o", &link)]).is_err());
        // Two outputs not yet written, at one place.
        let a = dir.path().join("r.json");
        let b = dir.path().join("sub").join("..").join("r.json");
        std::fs::create_dir(dir.path().join("sub")).unwrap();
        let e = refuse_overwriting(&inputs, &[named("-o", &a), named("--certificate", &b)])
            .unwrap_err();
        assert!(e.to_string().starts_with("--certificate"), "{e}");
        // Different files, standard output, and devices pass.
        let other = dir.path().join("other.json");
        let ok = [named("-o", &a), named("--certificate", &other)];
        assert!(refuse_overwriting(&inputs, &ok).is_ok());
        let dash = Path::new("-");
        assert!(refuse_overwriting(&[named("the mesh", dash)], &[named("-o", dash)]).is_ok());
        let null = Path::new("/dev/null");
        assert!(
            refuse_overwriting(&inputs, &[named("-o", null), named("--certificate", null)]).is_ok()
        );
        // A mesh named by a dataset (no such file) is not read from disk.
        let dataset = dir.path().join("unit_cube");
        let named_like_it = [named("-o", &dataset)];
        assert!(refuse_overwriting(&[named("the mesh", &dataset)], &named_like_it).is_ok());
    }
}
