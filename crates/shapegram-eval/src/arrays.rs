//! CGA's array functions (`sum`, `sortIndices`, `sortRowIndices`, `transpose`, `setElems`, the
//! array conversions) and `isNull`. A 2D array is an array of rows.

use std::cmp::Ordering;
use std::sync::Arc;

use crate::value::Value;

/// An array function: its result depends on its arguments alone.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ArrayFn {
    Sum,
    SortIndices,
    SortRowIndices,
    Transpose,
    FloatArray,
    StringArray,
    BoolArray,
    IsNull,
    SetElems,
}

/// The string CGA uses for a missing text value.
const NULL_STRING: &str = "\u{e000}";

impl ArrayFn {
    const ALL: [(&'static str, ArrayFn, &'static str); 9] = [
        ("sum", Self::Sum, "sum(array)"),
        ("sortIndices", Self::SortIndices, "sortIndices(array)"),
        (
            "sortRowIndices",
            Self::SortRowIndices,
            "sortRowIndices(array)",
        ),
        ("transpose", Self::Transpose, "transpose(array)"),
        ("floatArray", Self::FloatArray, "floatArray([values])"),
        ("stringArray", Self::StringArray, "stringArray([values])"),
        ("boolArray", Self::BoolArray, "boolArray([values])"),
        ("isNull", Self::IsNull, "isNull(value)"),
        (
            "setElems",
            Self::SetElems,
            "setElems(array, indices, values) | setElems(array, rowIndices, colIndices, values)",
        ),
    ];

    /// Every array function's name.
    pub fn names() -> impl Iterator<Item = &'static str> {
        Self::ALL.iter().map(|(name, _, _)| *name)
    }

    /// The function of this name.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().find(|(n, _, _)| *n == name).map(|e| e.1)
    }

    /// Fewest and most arguments.
    pub fn arity(self) -> (usize, usize) {
        match self {
            Self::FloatArray | Self::StringArray | Self::BoolArray => (0, 1),
            Self::SetElems => (3, 4),
            _ => (1, 1),
        }
    }

    /// The signature shown in hints.
    pub fn signature(self) -> &'static str {
        Self::ALL.iter().find(|e| e.1 == self).map_or("", |e| e.2)
    }

    /// The function on its arguments; an error message for arguments of the wrong kind.
    pub fn apply(self, args: &[Value]) -> Result<Value, String> {
        let Some(first) = args.first() else {
            // `floatArray()` and its kin: an empty array.
            return Ok(Value::Array(Arc::from([])));
        };
        match self {
            Self::IsNull => Ok(map_items(first, &|v| {
                Value::Bool(match v {
                    Value::Number(n) => n.is_nan(),
                    Value::Str(s) => &**s == NULL_STRING,
                    _ => false,
                })
            })),
            Self::FloatArray => convert(first, &|v| Value::Number(as_number(v))),
            Self::StringArray => convert(first, &|v| Value::string(&v.to_string())),
            Self::BoolArray => convert(first, &|v| Value::Bool(as_bool(v))),
            Self::Sum => sum(&flat(array(first)?)),
            Self::SortIndices => {
                let items = array(first)?;
                if items.iter().all(|i| matches!(i, Value::Array(_))) && !items.is_empty() {
                    // Each row of a 2D array separately.
                    let rows = items
                        .iter()
                        .map(|row| sort_indices(array(row)?))
                        .collect::<Result<Vec<_>, String>>()?;
                    return Ok(Value::Array(rows.into()));
                }
                sort_indices(items)
            }
            Self::SortRowIndices => {
                let rows = array(first)?;
                let mut order: Vec<usize> = (0..rows.len()).collect();
                let mut failure = None;
                order.sort_by(|&a, &b| {
                    compare_rows(&rows[a], &rows[b]).unwrap_or_else(|e| {
                        failure = Some(e);
                        Ordering::Equal
                    })
                });
                match failure {
                    Some(e) => Err(e),
                    None => Ok(indices(&order)),
                }
            }
            Self::Transpose => transpose(array(first)?),
            Self::SetElems => set_elems(array(first)?, &args[1..]),
        }
    }
}

fn array(v: &Value) -> Result<&[Value], String> {
    match v {
        Value::Array(items) => Ok(items),
        other => Err(format!("expected an array, found a {}", other.type_name())),
    }
}

/// The elements of an array, the rows of a 2D array run together.
fn flat(items: &[Value]) -> Vec<Value> {
    items
        .iter()
        .flat_map(|i| match i {
            Value::Array(row) => row.to_vec(),
            other => vec![other.clone()],
        })
        .collect()
}

/// `f` on a value, or on each element of an array (of each row of a 2D array).
fn map_items(v: &Value, f: &dyn Fn(&Value) -> Value) -> Value {
    match v {
        Value::Array(items) => Value::Array(items.iter().map(|i| map_items(i, f)).collect()),
        other => f(other),
    }
}

/// A conversion of each element; a single value becomes an array of one.
fn convert(v: &Value, f: &dyn Fn(&Value) -> Value) -> Result<Value, String> {
    Ok(match v {
        Value::Array(_) => map_items(v, f),
        other => Value::Array(Arc::from([f(other)])),
    })
}

/// `float()`'s reading of a value: strings are parsed (not a number: nan), `true` is 1.
fn as_number(v: &Value) -> f64 {
    match v {
        Value::Number(n) => *n,
        Value::Bool(b) => f64::from(u8::from(*b)),
        Value::Str(s) => s.trim().parse().unwrap_or(f64::NAN),
        Value::Array(_) => f64::NAN,
    }
}

/// `bool()`'s reading of a value: numbers other than 0, and the string "true".
fn as_bool(v: &Value) -> bool {
    match v {
        Value::Number(n) => *n != 0.0,
        Value::Bool(b) => *b,
        Value::Str(s) => &**s == "true",
        Value::Array(_) => false,
    }
}

fn sum(items: &[Value]) -> Result<Value, String> {
    if items.iter().all(|i| matches!(i, Value::Str(_))) && !items.is_empty() {
        return Ok(Value::string(
            &items.iter().map(ToString::to_string).collect::<String>(),
        ));
    }
    let mut total = 0.0;
    for item in items {
        total += match item {
            Value::Number(n) => *n,
            Value::Bool(b) => f64::from(u8::from(*b)),
            other => return Err(format!("cannot sum a {}", other.type_name())),
        };
    }
    Ok(Value::Number(total))
}

fn compare(a: &Value, b: &Value) -> Result<Ordering, String> {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => Ok(x.total_cmp(y)),
        (Value::Str(x), Value::Str(y)) => Ok(x.cmp(y)),
        (Value::Bool(x), Value::Bool(y)) => Ok(x.cmp(y)),
        _ => Err(format!(
            "cannot sort a {} against a {}",
            a.type_name(),
            b.type_name()
        )),
    }
}

/// Rows compare element by element; of two rows equal as far as both go, the shorter first.
fn compare_rows(a: &Value, b: &Value) -> Result<Ordering, String> {
    let (a, b) = (array(a)?, array(b)?);
    for (x, y) in a.iter().zip(b) {
        let order = compare(x, y)?;
        if order != Ordering::Equal {
            return Ok(order);
        }
    }
    Ok(a.len().cmp(&b.len()))
}

/// The indices that sort `items`, equal elements in their order (a stable sort).
fn sort_indices(items: &[Value]) -> Result<Value, String> {
    let mut order: Vec<usize> = (0..items.len()).collect();
    let mut failure = None;
    order.sort_by(|&a, &b| {
        compare(&items[a], &items[b]).unwrap_or_else(|e| {
            failure = Some(e);
            Ordering::Equal
        })
    });
    match failure {
        Some(e) => Err(e),
        None => Ok(indices(&order)),
    }
}

fn indices(order: &[usize]) -> Value {
    Value::Array(order.iter().map(|&i| Value::Number(i as f64)).collect())
}

/// Rows become columns; a 1D array is one row, and becomes a column of rows of one.
fn transpose(items: &[Value]) -> Result<Value, String> {
    let rows: Vec<&[Value]> = if items.iter().all(|i| matches!(i, Value::Array(_))) {
        items.iter().map(array).collect::<Result<_, _>>()?
    } else {
        vec![items]
    };
    let width = rows.first().map_or(0, |r| r.len());
    if rows.iter().any(|r| r.len() != width) {
        return Err("transpose needs rows of the same length".into());
    }
    let columns: Vec<Value> = (0..width)
        .map(|c| Value::Array(rows.iter().map(|r| r[c].clone()).collect()))
        .collect();
    Ok(Value::Array(columns.into()))
}

/// The positions an index selects among `len`: a number, an array of numbers, or a mask.
fn positions(at: &Value, len: usize) -> Result<Vec<usize>, String> {
    let one = |v: &Value| match v {
        Value::Number(i) if *i >= 0.0 && (i.floor() as usize) < len => Ok(i.floor() as usize),
        Value::Number(i) => Err(format!("index {i} is out of range for {len} elements")),
        other => Err(format!(
            "an index must be a number, found a {}",
            other.type_name()
        )),
    };
    match at {
        Value::Array(mask)
            if !mask.is_empty() && mask.iter().all(|m| matches!(m, Value::Bool(_))) =>
        {
            if mask.len() != len {
                return Err(format!(
                    "a mask of {} booleans cannot select from {len} elements",
                    mask.len()
                ));
            }
            Ok((0..len).filter(|&i| mask[i] == Value::Bool(true)).collect())
        }
        Value::Array(indices) => indices.iter().map(one).collect(),
        single => Ok(vec![one(single)?]),
    }
}

/// `setElems`: the array with the selected elements replaced, by one value or by the values
/// in the order of the selection (later repeats win).
fn set_elems(items: &[Value], args: &[Value]) -> Result<Value, String> {
    let values = &args[args.len() - 1];
    let mut out: Vec<Value> = items.to_vec();
    if args.len() == 2 {
        let at = positions(&args[0], out.len())?;
        for (k, &i) in at.iter().enumerate() {
            out[i] = pick(values, k, at.len())?;
        }
        return Ok(Value::Array(out.into()));
    }
    let rows = positions(&args[0], out.len())?;
    let width = out
        .first()
        .map_or(0, |r| array(r).map_or(0, <[Value]>::len));
    let columns = positions(&args[1], width)?;
    let cells: Vec<Value> = match values {
        Value::Array(value_rows) if value_rows.iter().all(|r| matches!(r, Value::Array(_))) => {
            flat(value_rows)
        }
        other => vec![other.clone(); rows.len() * columns.len()],
    };
    if cells.len() != rows.len() * columns.len() {
        return Err(format!(
            "setElems needs {} × {} values, found {}",
            rows.len(),
            columns.len(),
            cells.len()
        ));
    }
    for (r, &row) in rows.iter().enumerate() {
        let mut cells_of_row = array(&out[row])?.to_vec();
        for (c, &column) in columns.iter().enumerate() {
            cells_of_row[column] = cells[r * columns.len() + c].clone();
        }
        out[row] = Value::Array(cells_of_row.into());
    }
    Ok(Value::Array(out.into()))
}

/// The `k`th of `count` new values: the one value, or the `k`th of an array of `count`.
fn pick(values: &Value, k: usize, count: usize) -> Result<Value, String> {
    match values {
        Value::Array(items) if items.len() == count => Ok(items[k].clone()),
        Value::Array(items) => Err(format!(
            "setElems needs {count} values for {count} indices, found {}",
            items.len()
        )),
        one => Ok(one.clone()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn numbers(xs: &[f64]) -> Value {
        Value::Array(xs.iter().map(|&x| Value::Number(x)).collect())
    }

    fn strings(xs: &[&str]) -> Value {
        Value::Array(xs.iter().map(|x| Value::string(x)).collect())
    }

    #[test]
    fn sums_count_join_and_sort_as_the_reference_shows() {
        assert_eq!(
            ArrayFn::Sum.apply(&[numbers(&[1.0, 2.0, 3.0])]),
            Ok(Value::Number(6.0))
        );
        let flags = Value::Array(Arc::from([
            Value::Bool(true),
            Value::Bool(false),
            Value::Bool(true),
        ]));
        assert_eq!(ArrayFn::Sum.apply(&[flags]), Ok(Value::Number(2.0)));
        assert_eq!(
            ArrayFn::Sum.apply(&[strings(&["a", "b", "c"])]),
            Ok(Value::string("abc"))
        );
        assert_eq!(
            ArrayFn::SortIndices.apply(&[strings(&["c", "b", "d", "a"])]),
            Ok(numbers(&[3.0, 1.0, 0.0, 2.0]))
        );
        assert_eq!(
            ArrayFn::SortIndices.apply(&[numbers(&[2.0, 1.0, 3.0, 3.0, 1.0])]),
            Ok(numbers(&[1.0, 4.0, 0.0, 2.0, 3.0]))
        );
        let table = Value::Array(Arc::from([
            numbers(&[4.0, 0.0, 1.0]),
            numbers(&[2.0, 1.0, 9.0]),
            numbers(&[1.0, 3.0, 0.0]),
            numbers(&[2.0, 1.0, 0.0]),
        ]));
        assert_eq!(
            ArrayFn::SortRowIndices.apply(&[table]),
            Ok(numbers(&[2.0, 3.0, 1.0, 0.0]))
        );
    }

    #[test]
    fn set_elems_as_the_reference_shows() {
        let zeros = numbers(&[0.0; 6]);
        let set = |args: &[Value]| {
            let mut all = vec![zeros.clone()];
            all.extend_from_slice(args);
            ArrayFn::SetElems.apply(&all)
        };
        assert_eq!(
            set(&[Value::Number(2.0), Value::Number(1.0)]),
            Ok(numbers(&[0.0, 0.0, 1.0, 0.0, 0.0, 0.0]))
        );
        assert_eq!(
            set(&[numbers(&[5.0, 1.0, 3.0]), numbers(&[1.0, 2.0, 3.0])]),
            Ok(numbers(&[0.0, 2.0, 0.0, 3.0, 0.0, 1.0]))
        );
        assert_eq!(
            set(&[numbers(&[1.0, 1.0, 1.0]), numbers(&[1.0, 2.0, 3.0])]),
            Ok(numbers(&[0.0, 3.0, 0.0, 0.0, 0.0, 0.0]))
        );
        let grid = Value::Array(Arc::from([
            numbers(&[0.0; 3]),
            numbers(&[0.0; 3]),
            numbers(&[0.0; 3]),
        ]));
        let values = Value::Array(Arc::from([numbers(&[1.0, 2.0]), numbers(&[3.0, 4.0])]));
        assert_eq!(
            ArrayFn::SetElems.apply(&[grid, numbers(&[1.0, 2.0]), numbers(&[0.0, 2.0]), values]),
            Ok(Value::Array(Arc::from([
                numbers(&[0.0, 0.0, 0.0]),
                numbers(&[1.0, 0.0, 2.0]),
                numbers(&[3.0, 0.0, 4.0])
            ])))
        );
        assert_eq!(
            set(&[Value::Number(6.0), Value::Number(1.0)]),
            Err("index 6 is out of range for 6 elements".to_owned())
        );
    }

    #[test]
    fn transpose_conversions_and_nulls() {
        let table = Value::Array(Arc::from([
            strings(&["a", "b"]),
            strings(&["c", "d"]),
            strings(&["e", "f"]),
        ]));
        assert_eq!(
            ArrayFn::Transpose.apply(&[table]),
            Ok(Value::Array(Arc::from([
                strings(&["a", "c", "e"]),
                strings(&["b", "d", "f"])
            ])))
        );
        assert_eq!(
            ArrayFn::FloatArray.apply(&[]),
            Ok(Value::Array(Arc::from([])))
        );
        assert_eq!(
            ArrayFn::FloatArray
                .apply(&[strings(&["001.5", "x"])])
                .map(|v| v.to_string()),
            Ok("[1.5,NaN]".to_owned())
        );
        assert_eq!(
            ArrayFn::StringArray.apply(&[numbers(&[1.0, 2.5])]),
            Ok(strings(&["1", "2.5"]))
        );
        assert_eq!(
            ArrayFn::IsNull.apply(&[Value::Array(Arc::from([
                Value::Number(f64::NAN),
                Value::string("\u{e000}"),
                Value::string("")
            ]))]),
            Ok(Value::Array(Arc::from([
                Value::Bool(true),
                Value::Bool(true),
                Value::Bool(false)
            ])))
        );
        assert_eq!(
            ArrayFn::Sum.apply(&[Value::Number(1.0)]),
            Err("expected an array, found a number".to_owned())
        );
    }
}
