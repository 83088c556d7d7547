//! The model file's fixed-length rows (`[id, x, y]` nodes, `[x, y]` points, `[a, b]` bar nodes)
//! read to their exact length. TOML's reader takes a row longer than its fields and drops the rest
//! (`[1, 0.0, 0.0, 7.0]` read as `[1, 0.0, 0.0]`); JSON's refuses it; a model must mean one thing in
//! either form, so every row that holds more values than its fields is refused here, in both.

use super::file::NodeRow;
use serde::de::{self, Deserialize, Deserializer, IgnoredAny, SeqAccess, Visitor};
use std::fmt;
use std::marker::PhantomData;

/// The message of a row longer than its fields.
fn too_long<E: de::Error>(values: usize, fields: usize) -> E {
    E::custom(format!("a row holds more values than its fields ({values} values for {fields} fields)"))
}

/// After a row's fields: the values left in it, refused.
fn no_more<'de, A: SeqAccess<'de>>(mut seq: A, fields: usize) -> Result<(), A::Error> {
    let mut values = fields;
    while seq.next_element::<IgnoredAny>()?.is_some() {
        values += 1;
    }
    if values > fields {
        return Err(too_long(values, fields));
    }
    Ok(())
}

/// `N` values of `T`, exactly.
struct Exact<T, const N: usize>([T; N]);

impl<'de, T: Deserialize<'de>, const N: usize> Deserialize<'de> for Exact<T, N> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Row<T, const N: usize>(PhantomData<T>);
        impl<'de, T: Deserialize<'de>, const N: usize> Visitor<'de> for Row<T, N> {
            type Value = Exact<T, N>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                write!(f, "a row of {N} values")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Exact<T, N>, A::Error> {
                let mut values = Vec::with_capacity(N);
                for i in 0..N {
                    match seq.next_element::<T>()? {
                        Some(v) => values.push(v),
                        None => return Err(de::Error::invalid_length(i, &self)),
                    }
                }
                no_more(seq, N)?;
                let values: [T; N] = values.try_into().map_err(|_| de::Error::invalid_length(0, &self))?;
                Ok(Exact(values))
            }
        }
        deserializer.deserialize_seq(Row::<T, N>(PhantomData))
    }
}

/// A row of two values (`#[serde(deserialize_with = "…::pair")]`).
pub fn pair<'de, D: Deserializer<'de>, T: Deserialize<'de>>(d: D) -> Result<[T; 2], D::Error> {
    Exact::<T, 2>::deserialize(d).map(|row| row.0)
}

/// An optional row of two values.
pub fn optional_pair<'de, D: Deserializer<'de>, T: Deserialize<'de>>(d: D) -> Result<Option<[T; 2]>, D::Error> {
    Option::<Exact<T, 2>>::deserialize(d).map(|row| row.map(|r| r.0))
}

/// An optional list of rows of two values.
pub fn optional_pairs<'de, D: Deserializer<'de>, T: Deserialize<'de>>(d: D) -> Result<Option<Vec<[T; 2]>>, D::Error> {
    Option::<Vec<Exact<T, 2>>>::deserialize(d).map(|rows| rows.map(|rows| rows.into_iter().map(|r| r.0).collect()))
}

impl<'de> Deserialize<'de> for NodeRow {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Node;
        impl<'de> Visitor<'de> for Node {
            type Value = NodeRow;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a node row [id, x, y]")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<NodeRow, A::Error> {
                let id = seq.next_element()?.ok_or_else(|| de::Error::invalid_length(0, &self))?;
                let x = seq.next_element()?.ok_or_else(|| de::Error::invalid_length(1, &self))?;
                let y = seq.next_element()?.ok_or_else(|| de::Error::invalid_length(2, &self))?;
                no_more(seq, 3)?;
                Ok(NodeRow(id, x, y))
            }
        }
        deserializer.deserialize_seq(Node)
    }
}
