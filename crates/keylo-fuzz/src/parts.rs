//! Inputs made of several files: the parts are separated by [`SEPARATOR`].

/// The line that separates the files of a multi-file input.
pub const SEPARATOR: &[u8] = b"\n--keylo-fuzz-part--\n";

/// The first `N` parts of `data` (missing parts are empty; the last one takes the rest).
pub fn split<const N: usize>(data: &[u8]) -> [&[u8]; N] {
    let mut out = [&data[..0]; N];
    let mut rest = data;
    for (i, slot) in out.iter_mut().enumerate() {
        if i + 1 == N {
            *slot = rest;
            break;
        }
        match find(rest, SEPARATOR) {
            Some(at) => {
                *slot = &rest[..at];
                rest = &rest[at + SEPARATOR.len()..];
            }
            None => {
                *slot = rest;
                rest = &rest[rest.len()..];
            }
        }
    }
    out
}

/// Joins files into one input (the inverse of [`split`]), for making seeds.
pub fn join(parts: &[&[u8]]) -> Vec<u8> {
    parts.join(SEPARATOR)
}

fn find(haystack: &[u8], needle: &[u8]) -> Option<usize> {
    haystack.windows(needle.len()).position(|w| w == needle)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_inverts_join() {
        let joined = join(&[b"a", b"", b"ccc"]);
        assert_eq!(split::<3>(&joined), [&b"a"[..], b"", b"ccc"]);
        assert_eq!(split::<2>(b"only"), [&b"only"[..], b""]);
        assert_eq!(split::<2>(&joined)[1], &joined[2 + SEPARATOR.len() - 1..]);
    }
}
