//! `GrammarState`: the thesis's resource holding a grammar, the settings of its derivation and
//! the last derived mesh buffers.

use godot::classes::{Engine, FileAccess, IResource, ProjectSettings, Resource, SceneTree};
use godot::prelude::*;
use shapegram_eval::Value;
use shapegram_runtime::Error;

use crate::job::{Generator, Output, Request};

/// The name a grammar given as text goes by when no file names it (CGA or the notation it is in).
const TEXT_NAME: &str = "grammar";

/// A grammar, its seed, generations and attributes, and the mesh buffers of its last derivation.
/// Emits `changed` whenever new buffers arrive; `GrammarMesh` follows it.
#[derive(GodotClass)]
#[class(tool, base = Resource)]
pub struct GrammarState {
    /// The grammar file (`res://…` or an absolute path); its extension says the kind, and the
    /// files it imports are found beside it.
    #[export(file = "*.cga,*.mul,*.sgl,*.goal,*.lsys,*.cave,*.grammar")]
    #[var(set)]
    grammar_file: GString,
    /// The grammar as text; when set it is used instead of the file's (named by the file).
    #[export(multiline)]
    #[var(set)]
    grammar_text: GString,
    /// The seed of every random choice.
    #[export]
    #[var(set)]
    seed: i64,
    /// Generations (L-system iterations, topological generations); negative: the grammar's own.
    #[export]
    #[var(set)]
    generations: i32,
    /// Attribute values by name: numbers, strings and booleans.
    #[export]
    #[var(set)]
    attributes: VarDictionary,
    /// Derive whenever a setting changes (once per frame, however many changed).
    #[export]
    #[var(set)]
    auto_generate: bool,
    /// Derive automatic generations on a thread of their own, so a frame never waits on them.
    #[export]
    #[var]
    background: bool,
    /// The message of the last failed load or derivation (empty after one that succeeded).
    #[var(no_set)]
    last_error: GString,
    generator: Generator,
    output: Output,
    auto_pending: bool,
    base: Base<Resource>,
}

#[godot_api]
impl IResource for GrammarState {
    fn init(base: Base<Resource>) -> Self {
        Self {
            grammar_file: GString::new(),
            grammar_text: GString::new(),
            seed: 0,
            generations: -1,
            attributes: VarDictionary::new(),
            auto_generate: true,
            background: true,
            last_error: GString::new(),
            generator: Generator::default(),
            output: Output::default(),
            auto_pending: false,
            base,
        }
    }
}

#[godot_api]
impl GrammarState {
    /// Sets the grammar file.
    #[func]
    pub fn set_grammar_file(&mut self, path: GString) {
        self.grammar_file = path;
        self.settings_changed();
    }

    /// Sets the grammar text.
    #[func]
    pub fn set_grammar_text(&mut self, text: GString) {
        self.grammar_text = text;
        self.settings_changed();
    }

    /// Sets the seed.
    #[func]
    pub fn set_seed(&mut self, seed: i64) {
        self.seed = seed;
        self.settings_changed();
    }

    /// Sets the generations.
    #[func]
    pub fn set_generations(&mut self, generations: i32) {
        self.generations = generations;
        self.settings_changed();
    }

    /// Sets the attributes.
    #[func]
    pub fn set_attributes(&mut self, attributes: VarDictionary) {
        self.attributes = attributes;
        self.settings_changed();
    }

    /// Sets auto-generation (and generates when it is turned on).
    #[func]
    pub fn set_auto_generate(&mut self, on: bool) {
        self.auto_generate = on;
        self.settings_changed();
    }

    /// Derives now and waits for it; `changed` is emitted on success. Returns whether it
    /// succeeded (else `last_error` says why).
    #[func]
    pub fn generate(&mut self) -> bool {
        let result = self
            .load()
            .and_then(|request| self.generator.derive(&request));
        self.accept(result)
    }

    /// Starts deriving on a thread of its own (cancelling one still running); `changed` is
    /// emitted in the frame its result arrives. Returns whether it started.
    #[func]
    pub fn generate_in_background(&mut self) -> bool {
        match self
            .load()
            .and_then(|request| self.generator.start(request))
        {
            Ok(()) => {
                self.watch_frames(true);
                true
            }
            Err(error) => self.accept(Err(error)),
        }
    }

    /// Whether a background derivation is under way.
    #[func]
    pub fn is_generating(&self) -> bool {
        self.generator.is_running()
    }

    /// Takes the background derivation's result if it has arrived (called every frame while
    /// one runs); returns whether one arrived.
    #[func]
    pub fn poll(&mut self) -> bool {
        let Some(result) = self.generator.poll() else {
            return false;
        };
        self.watch_frames(false);
        self.accept(result);
        true
    }

    /// How many vertices the last derivation made.
    #[func]
    pub fn vertex_count(&self) -> i64 {
        self.output.vertex_count() as i64
    }

    /// The name of each part of the last derivation, in surface order.
    #[func]
    pub fn part_names(&self) -> PackedStringArray {
        self.output
            .part_names
            .iter()
            .map(|name| GString::from(name.as_str()))
            .collect()
    }

    /// The deferred automatic generation: one per frame, however many settings changed.
    #[func]
    fn auto_generate_now(&mut self) {
        self.auto_pending = false;
        if !self.auto_generate {
            return;
        }
        if self.background {
            self.generate_in_background();
        } else {
            self.generate();
        }
    }

    /// The buffers and part names of the last derivation.
    pub fn output(&self) -> &Output {
        &self.output
    }

    fn settings_changed(&mut self) {
        if self.auto_generate && !self.auto_pending {
            self.auto_pending = true;
            self.base_mut().call_deferred("auto_generate_now", &[]);
        }
    }

    /// While a background derivation runs, the scene tree's `process_frame` polls it.
    fn watch_frames(&mut self, on: bool) {
        let Some(tree) = Engine::singleton()
            .get_main_loop()
            .and_then(|main| main.try_cast::<SceneTree>().ok())
        else {
            return;
        };
        let callable = Callable::from_object_method(&self.to_gd(), "poll");
        let mut tree = tree.upcast::<Object>();
        let connected = tree.is_connected("process_frame", &callable);
        if on && !connected {
            tree.connect("process_frame", &callable);
        } else if !on && connected {
            tree.disconnect("process_frame", &callable);
        }
    }

    /// Loads the grammar the settings name (again only if it changed) and reads the request.
    fn load(&mut self) -> Result<Request, Error> {
        let file = self.grammar_file.to_string();
        let (name, text) = if self.grammar_text.is_empty() {
            if file.is_empty() {
                self.generator.unload();
                return Err(Error::new(
                    shapegram_runtime::ErrorKind::InvalidArgument,
                    "no grammar: set grammar_file or grammar_text",
                ));
            }
            let text = FileAccess::get_file_as_string(&file).to_string();
            let why = FileAccess::get_open_error();
            if why != godot::global::Error::OK {
                return Err(Error::new(
                    shapegram_runtime::ErrorKind::InvalidArgument,
                    format!("{file}: cannot read the grammar ({why:?})"),
                ));
            }
            (self.file_name(&file), text)
        } else if file.is_empty() {
            (TEXT_NAME.to_owned(), self.grammar_text.to_string())
        } else {
            (self.file_name(&file), self.grammar_text.to_string())
        };
        self.generator.load(&name, &text)?;
        Ok(Request {
            seed: self.seed as u64,
            attrs: attributes(&self.attributes)?,
            generations: u32::try_from(self.generations).ok(),
        })
    }

    /// The file's path on disk, so the engine finds the files it imports beside it.
    fn file_name(&self, file: &str) -> String {
        ProjectSettings::singleton()
            .globalize_path(file)
            .to_string()
    }

    /// Keeps a derivation's buffers and emits `changed`, or keeps the error; returns which.
    fn accept(&mut self, result: Result<Output, Error>) -> bool {
        match result {
            Ok(output) => {
                self.output = output;
                self.last_error = GString::new();
                self.base_mut().emit_changed();
                true
            }
            Err(error) => {
                godot_error!("GrammarState: {}", error.message);
                self.last_error = error.message.as_str().into();
                false
            }
        }
    }
}

/// The attributes as the engine takes them: numbers, strings and booleans.
fn attributes(dictionary: &VarDictionary) -> Result<Vec<(String, Value)>, Error> {
    dictionary
        .iter_shared()
        .map(|(key, value)| {
            let name = key.to_string();
            let value = match value.get_type() {
                VariantType::FLOAT => Value::Number(value.to::<f64>()),
                VariantType::INT => Value::Number(value.to::<i64>() as f64),
                VariantType::BOOL => Value::Bool(value.to::<bool>()),
                VariantType::STRING | VariantType::STRING_NAME => {
                    Value::Str(value.to_string().into())
                }
                other => {
                    return Err(Error::new(
                        shapegram_runtime::ErrorKind::AttributeType,
                        format!(
                            "the attribute `{name}` is a {other:?}: only numbers, strings and booleans are attributes"
                        ),
                    ));
                }
            };
            Ok((name, value))
        })
        .collect()
}
