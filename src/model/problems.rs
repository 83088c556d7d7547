//! A collector for model-file problems, so that `geoslip check` lists all of them at once.

use crate::error::Problem;

#[derive(Debug, Default)]
pub struct Problems {
    list: Vec<Problem>,
}

impl Problems {
    pub fn push(&mut self, field: impl Into<String>, entity: impl IntoEntity, message: impl Into<String>) {
        self.list.push(Problem { field: field.into(), entity: entity.into_entity(), message: message.into() });
    }

    pub fn len(&self) -> usize {
        self.list.len()
    }

    pub fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    pub fn into_vec(self) -> Vec<Problem> {
        self.list
    }
}

/// Something that can name the entity of a problem (or no entity).
pub trait IntoEntity {
    fn into_entity(self) -> Option<String>;
}

impl IntoEntity for &String {
    fn into_entity(self) -> Option<String> {
        Some(self.clone())
    }
}

impl IntoEntity for String {
    fn into_entity(self) -> Option<String> {
        Some(self)
    }
}

impl IntoEntity for &str {
    fn into_entity(self) -> Option<String> {
        Some(self.to_string())
    }
}

impl IntoEntity for Option<String> {
    fn into_entity(self) -> Option<String> {
        self
    }
}
