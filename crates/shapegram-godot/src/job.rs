//! Derivations without Godot: a loaded grammar, derived at once or on a thread of its own, into
//! mesh buffers. Nothing here touches an engine object, so a worker thread may run it.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::mpsc::{self, Receiver, TryRecvError};
use std::sync::{Arc, Mutex};
use std::thread;

use shapegram_eval::{DeriveControl, Value};
use shapegram_export::Buffers;
use shapegram_runtime::{Error, ErrorKind, Grammar, Settings};

/// What one derivation made: the buffers and the name of each part range in them.
#[derive(Debug, Default)]
pub struct Output {
    /// Positions, normals, indices and part ranges.
    pub buffers: Buffers,
    /// The name of each range of `buffers.parts`, in order.
    pub part_names: Vec<String>,
    /// The material name the grammar gave each range of `buffers.parts`, if any.
    pub part_materials: Vec<Option<String>>,
}

impl Output {
    /// How many vertices the buffers hold.
    pub fn vertex_count(&self) -> usize {
        self.buffers.positions.len()
    }
}

/// What a derivation is asked besides the grammar: the part of [`Settings`] a host sets.
#[derive(Clone, Debug, Default)]
pub struct Request {
    /// The seed.
    pub seed: u64,
    /// Attribute values overriding the grammar's, each checked against the grammar first.
    pub attrs: Vec<(String, Value)>,
    /// Generations; the grammar's own when `None`.
    pub generations: Option<u32>,
}

/// A grammar, shared with the thread deriving it.
type Shared = Arc<Mutex<Grammar>>;

/// Where a background derivation's result arrives.
type Pending = Receiver<Result<Output, Error>>;

/// A loaded grammar and at most one derivation of it running in the background.
#[derive(Default)]
pub struct Generator {
    /// The grammar and the name and text it was loaded from (to load it again only on a change).
    grammar: Option<(Shared, String, String)>,
    /// The running derivation: its control (to cancel it) and where its result arrives.
    running: Option<(Arc<DeriveControl>, Pending)>,
}

impl Generator {
    /// Loads `text`, named `name` (its extension says the kind), unless it is what is loaded.
    pub fn load(&mut self, name: &str, text: &str) -> Result<(), Error> {
        if let Some((_, loaded_name, loaded_text)) = &self.grammar
            && loaded_name == name
            && loaded_text == text
        {
            return Ok(());
        }
        self.grammar = None;
        let grammar = guarded(|| Grammar::load(name, text, None))?;
        self.grammar = Some((
            Arc::new(Mutex::new(grammar)),
            name.to_owned(),
            text.to_owned(),
        ));
        Ok(())
    }

    /// Forgets the grammar (and cancels its derivation).
    pub fn unload(&mut self) {
        self.cancel();
        self.grammar = None;
    }

    /// Derives the loaded grammar now, on the calling thread.
    pub fn derive(&mut self, request: &Request) -> Result<Output, Error> {
        self.cancel();
        run(self.grammar()?, request, Arc::new(DeriveControl::new()))
    }

    /// Starts deriving the loaded grammar on a thread of its own, cancelling the derivation
    /// still running; [`Generator::poll`] gives the result.
    pub fn start(&mut self, request: Request) -> Result<(), Error> {
        self.cancel();
        let grammar = self.grammar()?;
        let control = Arc::new(DeriveControl::new());
        let (sender, receiver) = mpsc::channel();
        let worker_control = Arc::clone(&control);
        thread::Builder::new()
            .name("shapegram-derive".into())
            .spawn(move || {
                // The receiver is gone when the derivation was cancelled: nobody waits.
                let _ = sender.send(run(grammar, &request, worker_control));
            })
            .map_err(|e| Error::derive(format!("cannot start a derivation thread: {e}")))?;
        self.running = Some((control, receiver));
        Ok(())
    }

    /// Whether a derivation started by [`Generator::start`] has not been polled yet.
    pub fn is_running(&self) -> bool {
        self.running.is_some()
    }

    /// The result of the background derivation once it has one (then it is no longer running).
    pub fn poll(&mut self) -> Option<Result<Output, Error>> {
        let (_, receiver) = self.running.as_ref()?;
        let result = match receiver.try_recv() {
            Ok(result) => result,
            Err(TryRecvError::Empty) => return None,
            Err(TryRecvError::Disconnected) => Err(Error::derive("the derivation thread ended")),
        };
        self.running = None;
        Some(result)
    }

    /// Cancels the background derivation, if one runs; its result is never polled.
    pub fn cancel(&mut self) {
        if let Some((control, _)) = self.running.take() {
            control.cancel();
        }
    }

    fn grammar(&self) -> Result<Shared, Error> {
        self.grammar
            .as_ref()
            .map(|(grammar, _, _)| Arc::clone(grammar))
            .ok_or_else(|| Error::new(ErrorKind::InvalidArgument, "no grammar is loaded"))
    }
}

impl Drop for Generator {
    fn drop(&mut self) {
        self.cancel();
    }
}

/// Checks the request's attributes, derives and fills the buffers.
fn run(grammar: Shared, request: &Request, control: Arc<DeriveControl>) -> Result<Output, Error> {
    guarded(|| {
        // A panic while deriving is caught below; the grammar inside is still whole.
        let grammar = grammar
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        for (name, value) in &request.attrs {
            grammar.check_attr(name, value)?;
        }
        let settings = Settings {
            seed: request.seed,
            attrs: request.attrs.clone(),
            generations: request.generations,
            control,
            ..Settings::default()
        };
        let derived = grammar.derive(&settings)?;
        let mut output = Output::default();
        derived.fill(&mut output.buffers);
        output.part_names = output
            .buffers
            .parts
            .iter()
            .map(|range| derived.part_name(range.part).to_owned())
            .collect();
        output.part_materials = output
            .buffers
            .parts
            .iter()
            .map(|range| derived.part_material(range.part).map(str::to_owned))
            .collect();
        Ok(output)
    })
}

/// Runs `f`, turning a panic into an error: no panic may reach Godot or end the worker thread
/// without a result.
fn guarded<T>(f: impl FnOnce() -> Result<T, Error>) -> Result<T, Error> {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or_else(|panic| {
        let what = panic
            .downcast_ref::<&str>()
            .map(|s| (*s).to_owned())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        Err(Error::derive(format!("internal error (a bug): {what}")))
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::{Duration, Instant};

    const HOUSE: &str = include_str!("../../../examples/house.cga");
    const TOPO_HOUSE: &str = include_str!("../../../examples/topo_house.grammar");

    fn wait(generator: &mut Generator) -> Result<Output, Error> {
        let start = Instant::now();
        loop {
            if let Some(result) = generator.poll() {
                return result;
            }
            assert!(start.elapsed() < Duration::from_secs(60), "no result");
            thread::sleep(Duration::from_millis(1));
        }
    }

    #[test]
    fn background_and_immediate_derivations_agree_byte_for_byte() {
        let mut generator = Generator::default();
        generator.load("house.cga", HOUSE).unwrap();
        let request = Request {
            seed: 7,
            ..Request::default()
        };
        let now = generator.derive(&request).unwrap();
        generator.start(request).unwrap();
        assert!(generator.is_running());
        let later = wait(&mut generator).unwrap();
        assert!(!generator.is_running());
        assert_eq!(now.buffers, later.buffers);
        assert_eq!(now.part_names, later.part_names);
        assert_eq!(now.part_names.len(), now.buffers.parts.len());
        assert!(now.vertex_count() > 0);
    }

    #[test]
    fn the_topological_house_has_its_parts_named() {
        let mut generator = Generator::default();
        generator.load("topo_house.grammar", TOPO_HOUSE).unwrap();
        let output = generator.derive(&Request::default()).unwrap();
        assert_eq!(output.part_names.len(), output.buffers.parts.len());
        assert!(output.part_names.iter().all(|name| !name.is_empty()));
        let counted: u32 = output.buffers.parts.iter().map(|p| p.vertex_count).sum();
        assert_eq!(counted as usize, output.vertex_count());
    }

    #[test]
    fn a_new_start_cancels_the_running_one() {
        let mut generator = Generator::default();
        generator.load("topo_house.grammar", TOPO_HOUSE).unwrap();
        let seed = |seed| Request {
            seed,
            ..Request::default()
        };
        // Seeds 1 and 2 give houses of 5,274 and 3,088 vertices: only the second may arrive.
        generator.start(seed(1)).unwrap();
        generator.start(seed(2)).unwrap();
        let polled = wait(&mut generator).unwrap();
        assert_eq!(polled.vertex_count(), 3088);
        assert_eq!(polled.buffers, generator.derive(&seed(2)).unwrap().buffers);
        assert!(generator.poll().is_none());
    }

    #[test]
    fn errors_carry_their_place_and_kind() {
        let mut generator = Generator::default();
        let error = generator.derive(&Request::default()).unwrap_err();
        assert_eq!(error.message, "no grammar is loaded");
        let error = generator
            .load("broken.cga", "Lot --> extrude(")
            .unwrap_err();
        assert_eq!(error.kind, ErrorKind::Grammar);
        assert!(
            error.message.contains("broken.cga:1:17"),
            "{}",
            error.message
        );
        generator.load("house.cga", HOUSE).unwrap();
        let request = Request {
            attrs: vec![("storeys".into(), Value::Str("three".into()))],
            ..Request::default()
        };
        let error = generator.derive(&request).unwrap_err();
        assert_eq!(error.kind, ErrorKind::AttributeType);
        generator.start(request).unwrap();
        assert_eq!(
            wait(&mut generator).unwrap_err().kind,
            ErrorKind::AttributeType
        );
    }
}
