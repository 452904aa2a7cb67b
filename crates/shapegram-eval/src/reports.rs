//! `report(key, value)` summarised as CityEngine's Procedural Runtime (PRT) summarises them:
//! per key `key_n`, `key_sum`, `key_avg`, `key_min` and `key_max`.

use rustc_hash::FxHashMap;

use crate::value::Value;

/// The reports summarised, keys in the order they first appear, each with its five entries.
/// Numbers and booleans (as 0 and 1) give count, sum, mean, least and greatest. For strings the
/// sum and the mean are the most frequent value (of equally frequent ones, the first reported)
/// and the least and greatest compare as text.
pub fn summarise_reports(reports: &[(String, Value)]) -> Vec<(String, Value)> {
    let mut keys: Vec<(&str, bool)> = Vec::new();
    for (key, value) in reports {
        let numeric = !matches!(value, Value::Str(_) | Value::Array(_));
        if !keys.contains(&(key.as_str(), numeric)) {
            keys.push((key, numeric));
        }
    }
    let mut out = Vec::with_capacity(keys.len() * 5);
    for (key, numeric) in keys {
        let values = reports
            .iter()
            .filter(|(k, v)| k == key && !matches!(v, Value::Str(_) | Value::Array(_)) == numeric)
            .map(|(_, v)| v);
        let summary = if numeric {
            numbers(values.map(|v| match v {
                Value::Number(n) => *n,
                _ => f64::from(u8::from(*v == Value::Bool(true))),
            }))
        } else {
            texts(values.map(ToString::to_string).collect())
        };
        for (suffix, value) in ["_n", "_sum", "_avg", "_min", "_max"]
            .into_iter()
            .zip(summary)
        {
            out.push((format!("{key}{suffix}"), value));
        }
    }
    out
}

fn numbers(values: impl Iterator<Item = f64>) -> [Value; 5] {
    let (mut n, mut sum, mut min, mut max) = (0.0, 0.0, f64::INFINITY, f64::NEG_INFINITY);
    for v in values {
        n += 1.0;
        sum += v;
        min = min.min(v);
        max = max.max(v);
    }
    [n, sum, sum / n, min, max].map(Value::Number)
}

fn texts(values: Vec<String>) -> [Value; 5] {
    // Each value's count and first position: a lot can report thousands of strings.
    let mut counts: FxHashMap<&str, (usize, usize)> = FxHashMap::default();
    for (i, v) in values.iter().enumerate() {
        counts.entry(v).or_insert((0, i)).0 += 1;
    }
    let most = counts
        .iter()
        .max_by_key(|(_, (n, first))| (*n, std::cmp::Reverse(*first)))
        .map_or("", |(v, _)| v);
    let min = values.iter().min().map_or(most, String::as_str);
    let max = values.iter().max().map_or(most, String::as_str);
    [
        Value::Number(values.len() as f64),
        Value::string(most),
        Value::string(most),
        Value::string(min),
        Value::string(max),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn entry(key: &str, value: Value) -> (String, Value) {
        (key.to_owned(), value)
    }

    #[test]
    fn numbers_booleans_and_strings_are_summarised_as_prt_does() {
        let reports = [
            entry("Area.Greenspace", Value::Number(600.0)),
            entry("open", Value::Bool(true)),
            entry("use", Value::string("shop")),
            entry("Area.Greenspace", Value::Number(200.0)),
            entry("open", Value::Bool(false)),
            entry("use", Value::string("flat")),
            entry("use", Value::string("flat")),
        ];
        let summary: Vec<String> = summarise_reports(&reports)
            .iter()
            .map(|(k, v)| format!("{k}={v}"))
            .collect();
        assert_eq!(
            summary,
            [
                "Area.Greenspace_n=2",
                "Area.Greenspace_sum=800",
                "Area.Greenspace_avg=400",
                "Area.Greenspace_min=200",
                "Area.Greenspace_max=600",
                "open_n=2",
                "open_sum=1",
                "open_avg=0.5",
                "open_min=0",
                "open_max=1",
                "use_n=3",
                "use_sum=flat",
                "use_avg=flat",
                "use_min=flat",
                "use_max=shop",
            ]
        );
        assert!(summarise_reports(&[]).is_empty());
    }
}
