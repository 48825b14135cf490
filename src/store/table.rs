//! A table as plain named columns of equal length ([`Table`], [`Column`]): what the reducer and
//! the report fill and the store writes to Parquet and CSV ([`super::summary`]). It lives here,
//! below them, so that the store never imports the reducer; no arrow in the type itself. Axis
//! columns are named by [`column_name`] (the data contract: `M` → `mass_main`, `m` →
//! `mass_inner`).

use super::schema::column_name;

/// One column of a table.
#[derive(Clone, Debug, PartialEq)]
pub enum Column {
    F64(Vec<f64>),
    /// Nullable unsigned integers.
    U64(Vec<Option<u64>>),
    Bool(Vec<bool>),
    Str(Vec<String>),
}

impl Column {
    pub fn len(&self) -> usize {
        match self {
            Column::F64(v) => v.len(),
            Column::U64(v) => v.len(),
            Column::Bool(v) => v.len(),
            Column::Str(v) => v.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Appends `other`'s cells (a column of the same type; another type is left as it is).
    pub fn extend(&mut self, other: Column) {
        match (self, other) {
            (Column::F64(a), Column::F64(b)) => a.extend(b),
            (Column::U64(a), Column::U64(b)) => a.extend(b),
            (Column::Bool(a), Column::Bool(b)) => a.extend(b),
            (Column::Str(a), Column::Str(b)) => a.extend(b),
            _ => {}
        }
    }

    /// Cell `i` as CSV text: shortest round-trip numbers, empty for NaN and null.
    pub fn cell(&self, i: usize) -> String {
        match self {
            Column::F64(v) if v[i].is_nan() => String::new(),
            Column::F64(v) => format!("{}", v[i]),
            Column::U64(v) => v[i].map(|x| x.to_string()).unwrap_or_default(),
            Column::Bool(v) => v[i].to_string(),
            Column::Str(v) => csv_quote(&v[i]),
        }
    }
}

fn csv_quote(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Named columns of equal length.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Table {
    pub columns: Vec<(String, Column)>,
}

impl Table {
    pub fn push(&mut self, name: impl Into<String>, col: Column) {
        self.columns.push((name.into(), col));
    }

    pub fn n_rows(&self) -> usize {
        self.columns.first().map_or(0, |c| c.1.len())
    }

    pub fn get(&self, name: &str) -> Option<&Column> {
        self.columns.iter().find(|c| c.0 == name).map(|c| &c.1)
    }

    /// RFC 4180 CSV with a header line.
    pub fn to_csv(&self) -> String {
        let mut out = Vec::new();
        // Writing to a Vec cannot fail.
        let _ = self.write_csv_header(&mut out);
        let _ = self.write_csv_rows(&mut out);
        String::from_utf8(out).unwrap_or_default()
    }

    /// The CSV header line.
    pub fn write_csv_header(&self, w: &mut impl std::io::Write) -> std::io::Result<()> {
        let names: Vec<&str> = self.columns.iter().map(|c| c.0.as_str()).collect();
        writeln!(w, "{}", names.join(","))
    }

    /// The CSV lines of every row.
    pub fn write_csv_rows(&self, w: &mut impl std::io::Write) -> std::io::Result<()> {
        for i in 0..self.n_rows() {
            let row: Vec<String> = self.columns.iter().map(|c| c.1.cell(i)).collect();
            writeln!(w, "{}", row.join(","))?;
        }
        Ok(())
    }

    /// Appends `other`'s rows (a table of the same columns, in the same order; an empty table
    /// takes `other` as it is).
    pub fn append(&mut self, other: Table) {
        if self.columns.is_empty() {
            *self = other;
            return;
        }
        for ((_, a), (_, b)) in self.columns.iter_mut().zip(other.columns) {
            a.extend(b);
        }
    }

    /// The columns named in `names`, in that order (names not in the table are left out).
    pub fn select(mut self, names: &[String]) -> Table {
        let mut columns = Vec::with_capacity(names.len());
        for n in names {
            if let Some(i) = self.columns.iter().position(|c| &c.0 == n) {
                columns.push(self.columns.swap_remove(i));
            }
        }
        Table { columns }
    }

    /// The rows `range` as a table of the same columns.
    pub fn rows(&self, range: std::ops::Range<usize>) -> Table {
        let columns = self
            .columns
            .iter()
            .map(|(name, c)| {
                let c = match c {
                    Column::F64(v) => Column::F64(v[range.clone()].to_vec()),
                    Column::U64(v) => Column::U64(v[range.clone()].to_vec()),
                    Column::Bool(v) => Column::Bool(v[range.clone()].to_vec()),
                    Column::Str(v) => Column::Str(v[range.clone()].to_vec()),
                };
                (name.clone(), c)
            })
            .collect();
        Table { columns }
    }
}

/// The column of an axis key in the tables ([`column_name`]: the data contract).
pub fn axis_column(key: &str) -> String {
    column_name(key).to_string()
}
