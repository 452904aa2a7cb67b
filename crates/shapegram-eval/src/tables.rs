//! `readStringTable` and `readFloatTable`: tables read from delimited text files, as
//! CityEngine reads them.
//!
//! The delimiter is the first of comma, semicolon and tab that the first line holds, else runs
//! of spaces. Fields are trimmed, and a field in double quotes loses them (`""` inside stands
//! for one quote). Empty lines are skipped. A table is a 2D array: an array of rows.

use std::sync::Arc;

use crate::value::Value;

/// The rows of a delimited text, each a list of fields.
pub(crate) fn rows(text: &str) -> Vec<Vec<String>> {
    let lines: Vec<&str> = text
        .lines()
        .map(|l| l.trim_end_matches('\r'))
        .filter(|l| !l.trim().is_empty())
        .collect();
    let delimiter = lines
        .first()
        .and_then(|first| [',', ';', '\t'].into_iter().find(|d| first.contains(*d)));
    lines
        .iter()
        .map(|line| match delimiter {
            Some(d) => split_quoted(line, d),
            None => line.split_whitespace().map(str::to_owned).collect(),
        })
        .collect()
}

/// A line split at `delimiter` outside double quotes.
fn split_quoted(line: &str, delimiter: char) -> Vec<String> {
    let mut fields = Vec::new();
    let mut field = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' if quoted && chars.peek() == Some(&'"') => {
                field.push('"');
                chars.next();
            }
            '"' => quoted = !quoted,
            c if c == delimiter && !quoted => fields.push(std::mem::take(&mut field)),
            c => field.push(c),
        }
    }
    fields.push(field);
    fields.into_iter().map(|f| f.trim().to_owned()).collect()
}

/// The table as strings.
pub(crate) fn string_table(rows: &[Vec<String>]) -> Value {
    Value::Array(
        rows.iter()
            .map(|row| Value::Array(row.iter().map(|f| Value::string(f)).collect::<Arc<[_]>>()))
            .collect(),
    )
}

/// The table as numbers, or the first field that is none: (row, column, text), counted from 0.
pub(crate) fn float_table(rows: &[Vec<String>]) -> Result<Value, (usize, usize, String)> {
    let mut table = Vec::with_capacity(rows.len());
    for (r, row) in rows.iter().enumerate() {
        let mut numbers = Vec::with_capacity(row.len());
        for (c, field) in row.iter().enumerate() {
            match field.parse::<f64>() {
                Ok(n) if n.is_finite() => numbers.push(Value::Number(n)),
                _ => return Err((r, c, field.clone())),
            }
        }
        table.push(Value::Array(numbers.into()));
    }
    Ok(Value::Array(table.into()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn delimiters_quotes_and_blank_lines() {
        assert_eq!(
            rows("name,height\n\"Oak, old\",12\n\nBirch , 8\r\n"),
            [
                vec!["name", "height"],
                vec!["Oak, old", "12"],
                vec!["Birch", "8"]
            ]
        );
        assert_eq!(rows("a;b\n1;2"), [vec!["a", "b"], vec!["1", "2"]]);
        assert_eq!(rows("a\tb\n1\t2"), [vec!["a", "b"], vec!["1", "2"]]);
        assert_eq!(
            rows("1  2 3\n4 5 6"),
            [vec!["1", "2", "3"], vec!["4", "5", "6"]]
        );
        assert_eq!(rows("\"say \"\"hi\"\"\",x"), [vec!["say \"hi\"", "x"]]);
    }

    #[test]
    fn a_float_table_names_its_first_field_that_is_no_number() {
        let t = float_table(&rows("1,2\n3,x")).unwrap_err();
        assert_eq!(t, (1, 1, "x".to_owned()));
        let Value::Array(table) = float_table(&rows("1,2\n3,4.5")).unwrap() else {
            panic!()
        };
        assert_eq!(table.len(), 2);
    }
}
