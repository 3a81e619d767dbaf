//! Label tables of label volumes: CSV, or a FreeSurfer colour look-up table (LUT).
//!
//! - CSV: `index,name[,...]` (RFC 4180 quoting, so a name may hold commas and quotes; an optional
//!   header line; further columns ignored).
//! - LUT: `index name r g b a`, colours 0..=255, `#` comments.
//! - Lines are numbered from 1.
//! - A table whose index is not an integer, whose label has no name, or which gives an index twice
//!   is refused with the line (both lines, for a repeat).
//! - A LUT colour that is not three integers in 0..=255 is a warning with its line, and the organ
//!   gets a colour of its own.

use crate::error::{Error, Result};
use std::collections::HashMap;
use std::path::Path;

/// One named label of a label table.
#[derive(Clone, Debug, PartialEq)]
pub struct Label {
    pub index: i64,
    pub name: String,
    /// sRGB in 0..=1, from a LUT.
    pub colour: Option<[f32; 3]>,
}

/// A label table's labels in file order, and warnings that did not stop the read.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LabelTable {
    pub labels: Vec<Label>,
    pub warnings: Vec<String>,
}

/// Reads a label table (at most [`crate::input::Kind::LabelTable`]'s size).
pub fn read_label_table(path: &Path) -> Result<LabelTable> {
    let text = crate::input::read_text(path, crate::input::Kind::LabelTable)?;
    parse_label_table(&text, path)
}

/// Parses a label table's text; `path` names it in errors and warnings.
pub fn parse_label_table(text: &str, path: &Path) -> Result<LabelTable> {
    let mut table = LabelTable::default();
    let mut first_line: HashMap<i64, usize> = HashMap::new();
    let mut data_lines = 0;
    for (n, line) in text.lines().enumerate() {
        let number = n + 1;
        let line = line.trim().trim_start_matches('\u{feff}');
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        data_lines += 1;
        let err = |m: String| Error::parse(path, Some(number), m);
        let csv = line.contains(',') || line.starts_with('"');
        let fields =
            if csv { csv_fields(line).map_err(err)? } else { line.split_whitespace().map(String::from).collect() };
        let Ok(index) = fields[0].trim().parse::<i64>() else {
            if data_lines == 1 {
                continue; // a header line
            }
            return Err(err(format!("label index `{}` is not an integer", shorten(&fields[0]))));
        };
        let name = fields.get(1).map(|f| f.trim()).unwrap_or("").to_string();
        if name.is_empty() {
            return Err(err(format!("label {index} has no name")));
        }
        if let Some(first) = first_line.insert(index, number) {
            return Err(err(format!("label {index} is given twice: on line {first} and on line {number}")));
        }
        let colour = if csv || fields.len() == 2 {
            None
        } else {
            let c: Vec<u8> = fields[2..fields.len().min(5)].iter().filter_map(|f| f.parse().ok()).collect();
            match c[..] {
                [r, g, b] => Some([r, g, b].map(|v| v as f32 / 255.0)),
                _ => {
                    table.warnings.push(format!(
                        "{}:{number}: colour `{}` of label {index} is not three integers 0..255: it gets a colour of its own",
                        path.display(),
                        shorten(&fields[2..].join(" "))
                    ));
                    None
                }
            }
        };
        table.labels.push(Label { index, name, colour });
    }
    if table.labels.is_empty() {
        return Err(Error::parse(path, None, "no labels in the table"));
    }
    Ok(table)
}

/// The fields of one CSV line: commas separate, a field in double quotes may hold commas, and `""`
/// inside quotes is one quote.
fn csv_fields(line: &str) -> std::result::Result<Vec<String>, String> {
    let mut fields = vec![String::new()];
    let mut chars = line.chars().peekable();
    let mut quoted = false;
    let mut was_quoted = false;
    while let Some(c) = chars.next() {
        let Some(field) = fields.last_mut() else { break };
        match (quoted, c) {
            (true, '"') if chars.peek() == Some(&'"') => {
                chars.next();
                field.push('"');
            }
            (true, '"') => quoted = false,
            (true, c) => field.push(c),
            (false, '"') if field.trim().is_empty() && !was_quoted => {
                field.clear();
                quoted = true;
                was_quoted = true;
            }
            (false, ',') => {
                fields.push(String::new());
                was_quoted = false;
            }
            (false, c) if was_quoted && !c.is_whitespace() => {
                return Err(format!("text `{c}` after the closing quote of field {}", fields.len()));
            }
            (false, c) => field.push(c),
        }
    }
    if quoted {
        return Err(format!("field {} opens a quote that the line does not close", fields.len()));
    }
    Ok(fields)
}

/// At most 40 characters of `s`, for messages.
fn shorten(s: &str) -> String {
    let mut out: String = s.chars().take(40).collect();
    if out.len() < s.len() {
        out.push('…');
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<LabelTable> {
        parse_label_table(text, Path::new("t.csv"))
    }

    #[test]
    fn csv_and_lut_tables() {
        let csv = parse("index,name\n0,Unknown\n17,Left-Hippocampus\n").unwrap();
        assert_eq!(csv.labels[1], Label { index: 17, name: "Left-Hippocampus".into(), colour: None });
        let lut = parse("# FreeSurfer\n  17  Left-Hippocampus  220 216 20 0\n").unwrap();
        assert_eq!(lut.labels[0].colour, Some([220.0 / 255.0, 216.0 / 255.0, 20.0 / 255.0]));
        assert!(lut.warnings.is_empty());
        let e = parse("index,name\n1,a\nx,b\n").unwrap_err().to_string();
        assert!(e.contains("t.csv:3"), "{e}");
        assert!(parse("").is_err());
    }

    #[test]
    fn quoted_names_hold_commas_and_quotes() {
        let t = parse("index,name,notes\n1,\"Nucleus accumbens, left\",x\n2,\"The \"\"red\"\" nucleus\"\n").unwrap();
        assert_eq!(t.labels[0].name, "Nucleus accumbens, left");
        assert_eq!(t.labels[1].name, "The \"red\" nucleus");
        let e = parse("1,\"open\n").unwrap_err().to_string();
        assert!(e.contains("t.csv:1") && e.contains("quote"), "{e}");
    }

    #[test]
    fn a_repeated_index_names_both_lines_and_a_bad_colour_warns() {
        let e = parse("1,a\n2,b\n# c\n1,c\n").unwrap_err().to_string();
        assert!(e.contains("t.csv:4") && e.contains("line 1 and on line 4"), "{e}");
        let t = parse("5 Left-Thing 300 0 0 0\n6 Right-Thing 1 2\n").unwrap();
        assert_eq!(t.labels.len(), 2);
        assert!(t.labels.iter().all(|l| l.colour.is_none()));
        assert_eq!(t.warnings.len(), 2, "{:?}", t.warnings);
        assert!(t.warnings[0].contains("t.csv:1") && t.warnings[0].contains("300 0 0 0"), "{:?}", t.warnings);
    }
}
