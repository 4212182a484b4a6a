//! RCPGenerator's plain text: one particle per line, `x1 … xd D`, separated by whitespace or
//! commas; `#` starts a comment; blank lines are ignored. The dimension is the column count
//! minus one.

use std::fmt::Write as _;

use crate::container::Container;
use crate::error::CoreError;
use crate::packing::{INSIDE_TOL, Packing};

/// The columns of a plain-text packing, before a container is attached.
#[derive(Clone, Debug, PartialEq)]
pub struct TextData {
    /// Dimension (columns − 1).
    pub dim: usize,
    /// Row-major positions.
    pub positions: Vec<f64>,
    /// Diameters.
    pub diameters: Vec<f64>,
    /// 1-based source line of each particle, for error messages.
    pub lines: Vec<usize>,
}

/// Parses plain text; `file` names the source in errors (`-` for standard input).
pub fn parse_text(file: &str, text: &str) -> Result<TextData, CoreError> {
    let mut data = TextData {
        dim: 0,
        positions: Vec::new(),
        diameters: Vec::new(),
        lines: Vec::new(),
    };
    let mut columns = 0usize;
    // Spreadsheets start UTF-8 files with a byte-order mark.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    for (ln, raw) in text.lines().enumerate() {
        let line = raw.split('#').next().unwrap_or("");
        let mut fields = Vec::new();
        let mut pos = 0usize;
        for tok in line.split(|c: char| c.is_whitespace() || c == ',') {
            if !tok.is_empty() {
                // Column of the token within the raw line (1-based).
                let col = line[pos..].find(tok).map_or(pos, |p| pos + p);
                fields.push((col + 1, tok));
                pos = col + tok.len();
            }
        }
        if fields.is_empty() {
            continue;
        }
        let err = |column: usize, message: String| CoreError::Parse {
            file: file.into(),
            line: ln + 1,
            column,
            message,
        };
        if columns == 0 {
            columns = fields.len();
            if columns < 3 {
                return Err(err(
                    1,
                    format!(
                        "{columns} column(s) found but a packing needs at least 3 (x, y and the diameter: d ≥ 2)"
                    ),
                ));
            }
            data.dim = columns - 1;
            if data.dim > crate::MAX_DIM {
                return Err(err(
                    1,
                    format!(
                        "{columns} columns give dimension {}, which is not supported: it must be between 2 and {}",
                        data.dim,
                        crate::MAX_DIM
                    ),
                ));
            }
        } else if fields.len() != columns {
            return Err(err(
                fields
                    .get(columns.min(fields.len()))
                    .map_or(line.len() + 1, |f| f.0),
                format!(
                    "{} columns here but {columns} on the first data line",
                    fields.len()
                ),
            ));
        }
        for (k, &(col, tok)) in fields.iter().enumerate() {
            let v: f64 = tok
                .parse()
                .map_err(|_| err(col, format!("`{}` is not a number", tok.escape_debug())))?;
            let shown = tok.escape_debug().to_string();
            if let Some(problem) = value_problem(v, k + 1 == columns, &shown) {
                return Err(err(col, problem));
            }
            if k + 1 == columns {
                data.diameters.push(v);
            } else {
                data.positions.push(v);
            }
        }
        data.lines.push(ln + 1);
    }
    if data.diameters.is_empty() {
        return Err(CoreError::File {
            file: file.into(),
            message: "no particles found (the file is empty or all comments)".into(),
        });
    }
    Ok(data)
}

/// Why `v` cannot be a coordinate (or a diameter, when `diameter`), as the sentence the reader
/// reports after the value's place; `shown` is the value as the user wrote it. `None` when it can.
pub fn value_problem(v: f64, diameter: bool, shown: &str) -> Option<String> {
    if !v.is_finite() {
        Some(format!("`{shown}` is not a finite number"))
    } else if diameter && v <= 0.0 {
        Some(format!("diameter {shown} must be positive"))
    } else {
        None
    }
}

/// Parses plain text and places it in `container` (which must have the file's dimension).
/// Particles outside the container are reported with their line.
pub fn read_packing(file: &str, text: &str, container: &Container) -> Result<Packing, CoreError> {
    let data = parse_text(file, text)?;
    if container.dim() != data.dim {
        return Err(CoreError::File {
            file: file.into(),
            message: format!(
                "the file has {} coordinate columns but the container (--box) has {} axes",
                data.dim,
                container.dim()
            ),
        });
    }
    let d = data.dim;
    let mut x = vec![0.0; d];
    for (i, &line) in data.lines.iter().enumerate() {
        if let Some(message) = container.too_wide_for_periodic_axis(data.diameters[i]) {
            return Err(CoreError::Parse {
                file: file.into(),
                line,
                column: d + 1,
                message,
            });
        }
        x.copy_from_slice(&data.positions[i * d..(i + 1) * d]);
        container.wrap(&mut x);
        if !container.contains(&x, 0.0, INSIDE_TOL * data.diameters[i]) {
            return Err(CoreError::Parse {
                file: file.into(),
                line,
                column: 1,
                message: format!(
                    "particle at ({}) lies outside the container ({}); check --box and --walls",
                    data.positions[i * d..(i + 1) * d]
                        .iter()
                        .map(|v| v.to_string())
                        .collect::<Vec<_>>()
                        .join(", "),
                    container.describe()
                ),
            });
        }
    }
    Packing::new(data.positions, data.diameters, container.clone())
}

/// Writes a packing as plain text, one particle per line, with round-trip precision.
pub fn write_text(packing: &Packing) -> String {
    let d = packing.dim;
    let mut s = String::with_capacity(packing.n() * (d + 1) * 22);
    for i in 0..packing.n() {
        for v in packing.position(i) {
            let _ = write!(s, "{v:e} ");
        }
        let _ = writeln!(s, "{:e}", packing.diameters[i]);
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_whitespace_commas_and_comments() {
        let t = "# header\n0.1 0.2 0.3 1\n\n0.5,0.5, 0.5, 2 # trailing\n";
        let d = parse_text("f.txt", t).unwrap();
        assert_eq!(d.dim, 3);
        assert_eq!(d.diameters, vec![1.0, 2.0]);
        assert_eq!(d.lines, vec![2, 4]);
    }

    #[test]
    fn errors_name_file_line_and_column() {
        let e = parse_text("f.txt", "0 0 1\n0 nan 1\n")
            .unwrap_err()
            .to_string();
        assert_eq!(e, "f.txt:2:3: `nan` is not a finite number");
        let e = parse_text("f.txt", "0 0 1\n0 0 -1\n")
            .unwrap_err()
            .to_string();
        assert_eq!(e, "f.txt:2:5: diameter -1 must be positive");
        let e = parse_text("f.txt", "0 0 1\n0 0 1 1\n")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("f.txt:2:7: 4 columns here but 3"), "{e}");
        let e = parse_text("f.txt", "0 0 1\n0 x 1\n")
            .unwrap_err()
            .to_string();
        assert_eq!(e, "f.txt:2:3: `x` is not a number");
        let e = parse_text("f.txt", "0 1\n").unwrap_err().to_string();
        assert!(e.contains("d ≥ 2"), "{e}");
        let e = parse_text("f.txt", "# nothing\n\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("no particles"), "{e}");
        let e = parse_text("f.txt", "0 0 inf\n").unwrap_err().to_string();
        assert!(e.contains("finite"), "{e}");
        // Too many columns: the file and line are named, not only the dimension.
        let row = vec!["0.5"; 20].join(" ");
        let e = parse_text("f.txt", &format!("# c\n{row}\n"))
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("f.txt:2:1: 20 columns give dimension 19, which is not supported"),
            "{e}"
        );
        // A NUL byte (a binary file) is shown escaped, never echoed raw.
        let e = parse_text("f.txt", "0 0\u{0}1 1\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("`0\\01` is not a number") && !e.contains('\0'),
            "{e}"
        );
    }

    #[test]
    fn a_byte_order_mark_is_skipped() {
        let d = parse_text("bom.txt", "\u{feff}0.1 0.2 1\n0.3 0.4 1\n").unwrap();
        assert_eq!(d.positions, vec![0.1, 0.2, 0.3, 0.4]);
        assert_eq!(d.lines, vec![1, 2]);
    }

    #[test]
    fn a_particle_wider_than_its_periodic_box_is_refused_with_its_line() {
        let c = Container::periodic_box(&[1.0, 1.0]).unwrap();
        let e = read_packing("f.txt", "0.5 0.5 0.1\n0.1 0.2 1e308\n", &c)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("f.txt:2:3: diameter 1e308 is wider than the periodic box length 1"),
            "{e}"
        );
        let e = Packing::new(vec![0.5, 0.5], vec![1.5], c.clone())
            .unwrap_err()
            .to_string();
        assert!(e.contains("overlap its own image"), "{e}");
        // As wide as the box: it touches its own image, as in a one-particle crystal.
        assert!(Packing::new(vec![0.5, 0.5], vec![1.0], c).is_ok());
        // Only periodic axes limit the diameter this way.
        let w = Container::with_flags(&[1.0, 4.0], &[true, false]).unwrap();
        assert!(read_packing("f.txt", "0.5 1.0 2\n", &w).is_ok());
    }

    #[test]
    fn particles_outside_the_container_are_located() {
        let c = Container::with_flags(&[1.0, 1.0], &[true, true]).unwrap();
        let e = read_packing("f.txt", "0.5 0.5 0.1\n# c\n1.5 0.5 0.1\n", &c)
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("f.txt:3:1: particle at (1.5, 0.5) lies outside"),
            "{e}"
        );
        let e = read_packing("f.txt", "0.5 0.5 0.5 0.1\n", &c)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("3 coordinate columns but the container (--box) has 2"),
            "{e}"
        );
        // Periodic axes wrap instead.
        let p = Container::periodic_box(&[1.0, 1.0]).unwrap();
        assert!(read_packing("f.txt", "1.5 -0.2 0.1\n", &p).is_ok());
    }

    #[test]
    fn text_round_trips_exactly() {
        let c = Container::periodic_box(&[1.0, 1.0, 1.0]).unwrap();
        let p = Packing::new(
            vec![0.1, 1.0 / 3.0, 0.7, 0.2, 0.4, 0.9],
            vec![0.123456789012345, 0.2],
            c.clone(),
        )
        .unwrap();
        let q = read_packing("-", &write_text(&p), &c).unwrap();
        assert_eq!(p, q);
    }
}
