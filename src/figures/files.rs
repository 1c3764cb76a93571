//! The figure registry, read from files: under `scenes/figures/`, one folder per set
//! holding `set.toml` (the set's title and place in the course, its key parameters, each
//! figure's caption and the facts to measure) and one ordinary scene file per figure,
//! `NN-name.toml`, which `lumiere render` reads as it reads any scene. Adding a figure is
//! adding its scene file and its entry in `set.toml`.
//!
//! Every error names the file, and for a bad value its line, column, field and what is
//! allowed; a scene file's errors are the scene format's own.

use super::Measure;
use crate::scene::{self, Scene, SceneError};
use serde_json::Value;
use std::ops::Range;
use std::path::{Path, PathBuf};
use toml::de::{DeTable, DeValue};

/// Where the figure files are, relative to the repository's root.
pub const DEFAULT_DIR: &str = "scenes/figures";
/// The file of a set's folder that describes the set.
pub const SET_FILE: &str = "set.toml";

/// One figure: its scene file and what `set.toml` says of it.
#[derive(Clone, Debug)]
pub struct Figure {
    /// File name without extension: `NN-short-name`.
    pub stem: String,
    /// The chapter's caption (French), drawn on the contact sheet.
    pub caption: String,
    pub scene: Scene,
    /// The scene file as found (`scenes/figures/mirrors/01-opening-60-depth-01.toml`), with
    /// `/` between the folder given to [`load`] and the rest.
    pub scene_file: String,
    /// FNV-1a 64 of the scene file's bytes.
    pub scene_hash: u64,
    pub measures: Vec<Measure>,
    /// The figure shows saturation on purpose: its white pixels are not a lighting fault.
    pub saturation_intended: bool,
    /// Why the figure's saturation is kept although it is not the figure's point (its scene
    /// follows the chapter's values, or is shared with figures that do not saturate).
    pub saturation_accepted: Option<String>,
    /// The set's key parameters as this figure's scene file writes them (`null` when the
    /// file leaves the value to its default), in the set's order.
    pub parameters: Vec<(String, Value)>,
}

/// A named set of figures, in the order of their numbers.
#[derive(Clone, Debug)]
pub struct FigureSet {
    /// The folder's name, also the output folder's and the command line's.
    pub name: String,
    /// Title of the contact sheet and gallery section.
    pub title: String,
    /// Place in the course: sets are listed by it.
    pub order: u32,
    /// The set's `set.toml`, as found.
    pub definition: String,
    pub figures: Vec<Figure>,
}

/// Why the figure files could not be read.
#[derive(Debug, thiserror::Error)]
pub enum RegistryError {
    /// A folder or file cannot be read.
    #[error("{}: {action}: {source}", path.display())]
    Io {
        path: PathBuf,
        action: &'static str,
        #[source]
        source: std::io::Error,
    },
    /// A value of a `set.toml` is wrong or missing.
    #[error("{file}:{line}:{column}: {field}: {message}")]
    Invalid {
        file: String,
        line: usize,
        column: usize,
        field: String,
        message: String,
    },
    /// A figure's scene file is not a valid scene.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// Files that do not go together: a scene file without an entry, an entry without a
    /// file, numbers that skip, two sets at one place.
    #[error("{path}: {message}")]
    Layout { path: String, message: String },
}

/// Every set under `dir`, by their `order`.
pub fn load(dir: &Path) -> Result<Vec<FigureSet>, RegistryError> {
    let mut sets = Vec::new();
    for entry in sorted_entries(dir)? {
        if !entry.is_dir() {
            continue;
        }
        sets.push(load_set(dir, &entry)?);
    }
    if sets.is_empty() {
        return Err(RegistryError::Layout {
            path: dir.display().to_string(),
            message: format!("no figure set (a folder holding a {SET_FILE})"),
        });
    }
    sets.sort_by_key(|s| s.order);
    for pair in sets.windows(2) {
        if pair[0].order == pair[1].order {
            return Err(RegistryError::Layout {
                path: pair[1].definition.clone(),
                message: format!(
                    "order = {} is also the order of {}; each set needs its own place",
                    pair[1].order, pair[0].definition
                ),
            });
        }
    }
    Ok(sets)
}

/// The entries of a folder, sorted by name.
fn sorted_entries(dir: &Path) -> Result<Vec<PathBuf>, RegistryError> {
    let read = std::fs::read_dir(dir).map_err(|source| RegistryError::Io {
        path: dir.to_path_buf(),
        action: "cannot read the folder of figure files",
        source,
    })?;
    let mut entries: Vec<PathBuf> = read.filter_map(|e| e.ok().map(|e| e.path())).collect();
    entries.sort();
    Ok(entries)
}

/// `a/b` with a `/` whatever the platform: the paths manifests and galleries record.
fn joined(dir: &str, name: &str) -> String {
    if dir.is_empty() || dir.ends_with('/') {
        format!("{dir}{name}")
    } else {
        format!("{dir}/{name}")
    }
}

/// A name of lower-case letters, digits and `-`, starting with a letter or digit.
fn is_name(s: &str) -> bool {
    s.chars()
        .next()
        .is_some_and(|c| c.is_ascii_lowercase() || c.is_ascii_digit())
        && s.chars()
            .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-')
}

/// The number of a figure stem `NN-name` (at least two digits, then a name).
fn stem_number(stem: &str) -> Option<u32> {
    let (digits, name) = stem.split_once('-')?;
    (digits.len() >= 2 && digits.chars().all(|c| c.is_ascii_digit()) && is_name(name))
        .then(|| digits.parse().ok())
        .flatten()
}

fn load_set(dir: &Path, folder: &Path) -> Result<FigureSet, RegistryError> {
    let name = folder
        .file_name()
        .and_then(|n| n.to_str())
        .unwrap_or_default()
        .to_string();
    let folder_text = joined(&dir.display().to_string(), &name);
    if !is_name(&name) {
        return Err(RegistryError::Layout {
            path: folder_text,
            message: "a set's folder name must be lower-case letters, digits and '-'".into(),
        });
    }
    let set_path = folder.join(SET_FILE);
    let definition = joined(&folder_text, SET_FILE);
    let bytes = crate::limits::read_file(&set_path).map_err(|source| RegistryError::Io {
        path: set_path.clone(),
        action: "cannot read the set's description",
        source,
    })?;
    let text = scene::text_of(bytes, &definition)?;
    let doc = SetDoc::parse(&definition, &text)?;
    // The scene files of the folder: every `.toml` but set.toml.
    let mut scene_files: Vec<String> = Vec::new();
    for path in sorted_entries(folder)? {
        let file = path.file_name().and_then(|n| n.to_str()).unwrap_or_default();
        if path.is_file() && file.ends_with(".toml") && file != SET_FILE {
            scene_files.push(file.trim_end_matches(".toml").to_string());
        }
    }
    for stem in &scene_files {
        if !doc.entries.iter().any(|e| e.stem == *stem) {
            return Err(RegistryError::Layout {
                path: joined(&folder_text, &format!("{stem}.toml")),
                message: format!("no entry [figures.{stem}] in {definition} gives this figure its caption"),
            });
        }
    }
    let mut figures = Vec::new();
    for (i, entry) in doc.entries.iter().enumerate() {
        if entry.number != i as u32 + 1 {
            return Err(doc.invalid(
                entry.span.clone(),
                &format!("figures.{}", entry.stem),
                format!(
                    "figures are numbered 01, 02, ... without a gap: expected number {:02}, got {:02}",
                    i + 1,
                    entry.number
                ),
            ));
        }
        if !scene_files.contains(&entry.stem) {
            return Err(doc.invalid(
                entry.span.clone(),
                &format!("figures.{}", entry.stem),
                format!("no scene file {}.toml beside this file", entry.stem),
            ));
        }
        let file = joined(&folder_text, &format!("{}.toml", entry.stem));
        let path = folder.join(format!("{}.toml", entry.stem));
        let bytes = crate::limits::read_file(&path).map_err(|source| RegistryError::Io {
            path: path.clone(),
            action: "cannot read the scene file",
            source,
        })?;
        let scene_text = scene::text_of(bytes, &file)?;
        let scene = scene::parse(&scene_text, &file)?;
        let table: toml::Table = scene_text.parse().map_err(|e: toml::de::Error| RegistryError::Layout {
            path: file.clone(),
            message: e.message().to_string(),
        })?;
        let parameters = doc
            .key_parameters
            .iter()
            .map(|p| (p.clone(), parameter(&table, p)))
            .collect();
        let mut measures = doc.measures.clone();
        for m in &entry.measures {
            if !measures.contains(m) {
                measures.push(*m);
            }
        }
        figures.push(Figure {
            stem: entry.stem.clone(),
            caption: entry.caption.clone(),
            scene,
            scene_hash: crate::film::fnv1a64(scene_text.as_bytes()),
            scene_file: file,
            measures,
            saturation_intended: entry.saturation_intended,
            saturation_accepted: entry.saturation_accepted.clone(),
            parameters,
        });
    }
    Ok(FigureSet {
        name,
        title: doc.title,
        order: doc.order,
        definition,
        figures,
    })
}

/// The value at `path` (`render.depth`, `lights`, `shapes[1].opening`) of a TOML table, as
/// JSON; `null` when the file does not write it.
fn parameter(table: &toml::Table, path: &str) -> Value {
    let mut value: Option<toml::Value> = Some(toml::Value::Table(table.clone()));
    for seg in path_segments(path).unwrap_or_default() {
        value = match (seg, value) {
            (Seg::Key(k), Some(toml::Value::Table(t))) => t.get(&k).cloned(),
            (Seg::Index(i), Some(toml::Value::Array(a))) => a.get(i).cloned(),
            _ => None,
        };
    }
    value.map_or(Value::Null, |v| serde_json::to_value(v).unwrap_or(Value::Null))
}

enum Seg {
    Key(String),
    Index(usize),
}

/// `a.b[2].c` as keys and indices; `None` if it is not of that form.
fn path_segments(path: &str) -> Option<Vec<Seg>> {
    let mut segs = Vec::new();
    for part in path.split('.') {
        let (key, mut rest) = part.split_once('[').map_or((part, ""), |(k, r)| (k, r));
        if key.is_empty() || !key.chars().all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-') {
            return None;
        }
        segs.push(Seg::Key(key.to_string()));
        while !rest.is_empty() {
            let (index, after) = rest.split_once(']')?;
            segs.push(Seg::Index(index.parse().ok()?));
            rest = match after {
                "" => "",
                a => a.strip_prefix('[')?,
            };
        }
    }
    Some(segs)
}

/// What `set.toml` says of one figure.
struct Entry {
    stem: String,
    number: u32,
    caption: String,
    measures: Vec<Measure>,
    saturation_intended: bool,
    saturation_accepted: Option<String>,
    /// The entry's key in the file.
    span: Range<usize>,
}

/// A `set.toml`, checked.
struct SetDoc<'a> {
    file: &'a str,
    text: &'a str,
    title: String,
    order: u32,
    key_parameters: Vec<String>,
    measures: Vec<Measure>,
    entries: Vec<Entry>,
}

/// The facts a figure may measure, as `set.toml` names them.
const MEASURES: [(&str, Measure); 2] = [
    ("attenuation_range", Measure::AttenuationRange),
    ("cone_images", Measure::ConeImages),
];

impl<'a> SetDoc<'a> {
    fn invalid(&self, span: Range<usize>, field: &str, message: String) -> RegistryError {
        let before = &self.text[..span.start.min(self.text.len())];
        RegistryError::Invalid {
            file: self.file.to_string(),
            line: before.matches('\n').count() + 1,
            column: before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1,
            field: field.to_string(),
            message,
        }
    }

    fn parse(file: &'a str, text: &'a str) -> Result<Self, RegistryError> {
        let mut doc = SetDoc {
            file,
            text,
            title: String::new(),
            order: 0,
            key_parameters: Vec::new(),
            measures: Vec::new(),
            entries: Vec::new(),
        };
        let root = DeTable::parse(text)
            .map_err(|e| doc.invalid(e.span().unwrap_or(0..0), "TOML", e.message().trim().to_string()))?;
        let whole = 0..0;
        let (mut title, mut order, mut figures) = (None, None, None);
        for (key, value) in root.get_ref().iter() {
            let k = key.get_ref().as_ref();
            match k {
                "title" => title = Some(doc.string(value, k)?),
                "order" => order = Some(doc.whole_number(value, k, 1)?),
                "key_parameters" => {
                    for (i, item) in doc.array(value, k)?.iter().enumerate() {
                        let field = format!("{k}[{i}]");
                        let p = doc.string(item, &field)?;
                        if path_segments(&p).is_none() {
                            return Err(doc.invalid(
                                item.span(),
                                &field,
                                format!(
                                    "must be a field path of the scene format such as \"render.depth\" or \"shapes[1].opening\", got {p:?}"
                                ),
                            ));
                        }
                        doc.key_parameters.push(p);
                    }
                }
                "measure" => doc.measures = doc.measures(value, k)?,
                "figures" => figures = Some(value),
                _ => {
                    return Err(doc.invalid(
                        key.span(),
                        k,
                        format!("unknown field `{k}`, expected one of `title`, `order`, `key_parameters`, `measure`, `figures`"),
                    ));
                }
            }
        }
        let missing = |field: &str| doc.invalid(whole.clone(), field, "missing: every set.toml gives it".into());
        let title = title.ok_or_else(|| missing("title"))?;
        let order = order.ok_or_else(|| missing("order"))?;
        let figures = figures.ok_or_else(|| missing("figures"))?;
        (doc.title, doc.order) = (title, order);
        let DeValue::Table(table) = figures.get_ref() else {
            return Err(doc.invalid(
                figures.span(),
                "figures",
                "must be a table of figures, [figures.NN-name]".into(),
            ));
        };
        for (key, value) in table.iter() {
            let stem = key.get_ref().to_string();
            let field = format!("figures.{stem}");
            let Some(number) = stem_number(&stem) else {
                return Err(doc.invalid(
                    key.span(),
                    &field,
                    "a figure is named NN-name: two or more digits, '-', then lower-case letters, digits and '-'"
                        .into(),
                ));
            };
            doc.entries.push(doc.entry(stem, number, key.span(), value, &field)?);
        }
        if doc.entries.is_empty() {
            return Err(doc.invalid(figures.span(), "figures", "the set has no figure".into()));
        }
        doc.entries.sort_by_key(|e| e.number);
        Ok(doc)
    }

    fn entry(
        &self,
        stem: String,
        number: u32,
        span: Range<usize>,
        value: &toml::Spanned<DeValue>,
        field: &str,
    ) -> Result<Entry, RegistryError> {
        let DeValue::Table(table) = value.get_ref() else {
            return Err(self.invalid(value.span(), field, "must be a table with a caption".into()));
        };
        let mut entry = Entry {
            stem,
            number,
            caption: String::new(),
            measures: Vec::new(),
            saturation_intended: false,
            saturation_accepted: None,
            span,
        };
        let mut caption = None;
        for (key, v) in table.iter() {
            let k = key.get_ref().as_ref();
            let f = format!("{field}.{k}");
            match k {
                "caption" => caption = Some(self.string(v, &f)?),
                "measure" => entry.measures = self.measures(v, &f)?,
                "saturation_intended" => match v.get_ref() {
                    DeValue::Boolean(b) => entry.saturation_intended = *b,
                    _ => return Err(self.invalid(v.span(), &f, "must be true or false".into())),
                },
                "saturation_accepted" => entry.saturation_accepted = Some(self.string(v, &f)?),
                _ => {
                    return Err(self.invalid(
                        key.span(),
                        &f,
                        format!(
                            "unknown field `{k}`, expected one of `caption`, `measure`, `saturation_intended`, `saturation_accepted`"
                        ),
                    ));
                }
            }
        }
        entry.caption = caption.ok_or_else(|| {
            self.invalid(
                entry.span.clone(),
                &format!("{field}.caption"),
                "missing: every figure has a caption".into(),
            )
        })?;
        Ok(entry)
    }

    fn string(&self, value: &toml::Spanned<DeValue>, field: &str) -> Result<String, RegistryError> {
        match value.get_ref() {
            DeValue::String(s) if !s.trim().is_empty() => Ok(s.to_string()),
            _ => Err(self.invalid(value.span(), field, "must be a non-empty string".into())),
        }
    }

    fn whole_number(&self, value: &toml::Spanned<DeValue>, field: &str, min: u32) -> Result<u32, RegistryError> {
        let parsed = match value.get_ref() {
            DeValue::Integer(i) => i.as_str().parse::<u32>().ok(),
            _ => None,
        };
        parsed.filter(|&n| n >= min).ok_or_else(|| {
            self.invalid(
                value.span(),
                field,
                format!("must be a whole number in [{min}, {}]", u32::MAX),
            )
        })
    }

    fn array<'v>(
        &self,
        value: &'v toml::Spanned<DeValue<'a>>,
        field: &str,
    ) -> Result<&'v [toml::Spanned<DeValue<'a>>], RegistryError> {
        match value.get_ref() {
            DeValue::Array(a) => Ok(a.as_ref()),
            _ => Err(self.invalid(value.span(), field, "must be an array".into())),
        }
    }

    fn measures(&self, value: &toml::Spanned<DeValue<'a>>, field: &str) -> Result<Vec<Measure>, RegistryError> {
        let mut out = Vec::new();
        for (i, item) in self.array(value, field)?.iter().enumerate() {
            let f = format!("{field}[{i}]");
            let name = self.string(item, &f)?;
            let Some((_, m)) = MEASURES.iter().find(|(n, _)| *n == name) else {
                return Err(self.invalid(
                    item.span(),
                    &f,
                    format!("must be \"attenuation_range\" or \"cone_images\", got {name:?}"),
                ));
            };
            out.push(*m);
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stems_and_paths() {
        assert_eq!(stem_number("01-ambient"), Some(1));
        assert_eq!(stem_number("21-depth-20"), Some(21));
        assert_eq!(stem_number("1-ambient"), None);
        assert_eq!(stem_number("01-Ambient"), None);
        assert_eq!(stem_number("01-"), None);
        assert!(path_segments("shapes[1].opening").is_some_and(|s| s.len() == 3));
        assert!(path_segments("a[1][2]").is_some_and(|s| s.len() == 3));
        assert!(path_segments("a..b").is_none());
        assert!(path_segments("a[x]").is_none());
        let t: toml::Table = "[render]\ndepth = 3\n[[shapes]]\ntype = \"plane\"\n[[shapes]]\nopening = 60\n"
            .parse()
            .unwrap();
        assert_eq!(parameter(&t, "render.depth"), serde_json::json!(3));
        assert_eq!(parameter(&t, "shapes[1].opening"), serde_json::json!(60));
        assert_eq!(parameter(&t, "render.shadows"), Value::Null);
    }

    #[test]
    fn set_file_errors_are_located() {
        let err = |text: &str| SetDoc::parse("s/set.toml", text).err().unwrap().to_string();
        assert_eq!(
            err("title = \"T\"\norder = 0\n[figures.01-a]\ncaption = \"c\"\n"),
            "s/set.toml:2:9: order: must be a whole number in [1, 4294967295]"
        );
        assert_eq!(
            err("title = \"T\"\norder = 1\n[figures.01-a]\ncaptoin = \"c\"\n"),
            "s/set.toml:4:1: figures.01-a.captoin: unknown field `captoin`, expected one of `caption`, `measure`, `saturation_intended`, `saturation_accepted`"
        );
        assert_eq!(
            err("title = \"T\"\norder = 1\nmeasure = [\"cones\"]\n[figures.01-a]\ncaption = \"c\"\n"),
            "s/set.toml:3:12: measure[0]: must be \"attenuation_range\" or \"cone_images\", got \"cones\""
        );
        assert_eq!(
            err("title = \"T\"\norder = 1\n[figures.1-a]\ncaption = \"c\"\n"),
            "s/set.toml:3:10: figures.1-a: a figure is named NN-name: two or more digits, '-', then lower-case letters, digits and '-'"
        );
        assert_eq!(
            err("title = \"T\"\norder = 1\n"),
            "s/set.toml:1:1: figures: missing: every set.toml gives it"
        );
    }
}
