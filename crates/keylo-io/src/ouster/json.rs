//! Typed access to a JSON tree with errors that name the file and the key path.

use std::path::Path;

use serde_json::Value;

use crate::IoError;

/// A JSON object with the path that leads to it, for messages.
pub struct Node<'a> {
    pub file: &'a Path,
    pub path: String,
    pub value: &'a Value,
}

impl<'a> Node<'a> {
    /// The document root.
    pub fn root(file: &'a Path, value: &'a Value) -> Self {
        Self {
            file,
            path: String::new(),
            value,
        }
    }

    fn key_path(&self, key: &str) -> String {
        if self.path.is_empty() {
            key.to_string()
        } else {
            format!("{}.{key}", self.path)
        }
    }

    fn error(&self, key: &str, expected: &str) -> IoError {
        IoError::format(
            self.file,
            format!("metadata key `{}`: expected {expected}", self.key_path(key)),
        )
    }

    /// The child object `key`, if present.
    pub fn child(&self, key: &str) -> Option<Node<'a>> {
        let value = self.value.get(key)?;
        value.is_object().then(|| Node {
            file: self.file,
            path: self.key_path(key),
            value,
        })
    }

    /// A number, if present; an error if present with another type.
    pub fn opt_f64(&self, key: &str) -> Result<Option<f64>, IoError> {
        match self.value.get(key) {
            None | Some(Value::Null) => Ok(None),
            Some(v) => v
                .as_f64()
                .filter(|x| x.is_finite())
                .map(Some)
                .ok_or_else(|| self.error(key, "a finite number")),
        }
    }

    /// A non-negative integer, if present.
    pub fn opt_usize(&self, key: &str) -> Result<Option<usize>, IoError> {
        match self.value.get(key) {
            None | Some(Value::Null) => Ok(None),
            Some(v) => v
                .as_u64()
                .map(|x| Some(x as usize))
                .ok_or_else(|| self.error(key, "a non-negative integer")),
        }
    }

    /// An unsigned integer written as a number or a decimal string (serial numbers are
    /// either), if present.
    pub fn opt_u64_lenient(&self, key: &str) -> Result<Option<u64>, IoError> {
        match self.value.get(key) {
            None | Some(Value::Null) => Ok(None),
            Some(Value::String(s)) if s.trim().is_empty() => Ok(None),
            Some(Value::String(s)) => s
                .trim()
                .parse()
                .map(Some)
                .map_err(|_| self.error(key, "an unsigned integer")),
            Some(v) => v
                .as_u64()
                .map(Some)
                .ok_or_else(|| self.error(key, "an unsigned integer")),
        }
    }

    /// A string, if present.
    pub fn opt_str(&self, key: &str) -> Result<Option<&'a str>, IoError> {
        match self.value.get(key) {
            None | Some(Value::Null) => Ok(None),
            Some(v) => v
                .as_str()
                .map(Some)
                .ok_or_else(|| self.error(key, "a string")),
        }
    }

    /// A list of finite numbers, if present.
    pub fn opt_f64s(&self, key: &str) -> Result<Option<Vec<f64>>, IoError> {
        let Some(v) = self.value.get(key) else {
            return Ok(None);
        };
        let list = v
            .as_array()
            .ok_or_else(|| self.error(key, "a list of numbers"))?;
        list.iter()
            .map(|x| x.as_f64().filter(|f| f.is_finite()))
            .collect::<Option<Vec<f64>>>()
            .map(Some)
            .ok_or_else(|| self.error(key, "a list of finite numbers"))
    }

    /// A list of integers, if present.
    pub fn opt_i64s(&self, key: &str) -> Result<Option<Vec<i64>>, IoError> {
        let Some(v) = self.value.get(key) else {
            return Ok(None);
        };
        let list = v
            .as_array()
            .ok_or_else(|| self.error(key, "a list of integers"))?;
        list.iter()
            .map(Value::as_i64)
            .collect::<Option<Vec<i64>>>()
            .map(Some)
            .ok_or_else(|| self.error(key, "a list of integers"))
    }

    /// A required list of finite numbers.
    pub fn f64s(&self, key: &str) -> Result<Vec<f64>, IoError> {
        self.opt_f64s(key)?
            .ok_or_else(|| self.error(key, "a list of numbers (missing)"))
    }

    /// A list of exactly `n` numbers, if present.
    pub fn opt_f64s_len(&self, key: &str, n: usize) -> Result<Option<Vec<f64>>, IoError> {
        match self.opt_f64s(key)? {
            Some(v) if v.len() != n => {
                Err(self.error(key, &format!("{n} numbers, found {}", v.len())))
            }
            other => Ok(other),
        }
    }
}
