//! The thread that runs the checks, one at a time, so that the server
//! keeps answering while a save check explores. A newer text of a document
//! replaces its check still waiting in the queue; a check running when its
//! document changes is cancelled ([`Running::supersede`]: it stops at its
//! next limit test, as if its deadline had passed) and its result dropped
//! by the server (by its generation).

use std::collections::BTreeMap;
use std::sync::{Arc, Mutex};

use crossbeam_channel::{Receiver, Sender, unbounded};

use super::check::{self, Done, Job, Settings};

/// The checks need the deep stack the command line's worker has (deep
/// but legal inputs must never overflow it).
const STACK_BYTES: usize = 256 * 1024 * 1024;

/// The check thread's two ends.
pub struct Worker {
    /// Where to send checks to run.
    pub jobs: Sender<Job>,
    /// Where finished checks come back.
    pub done: Receiver<Done>,
    /// The check running now.
    pub running: Arc<Running>,
}

/// The document (URI) and generation of the check running now, if any.
/// Its lock makes "is it still running" and "cancel it" one step, so that
/// a cancel never reaches the next check.
#[derive(Debug, Default)]
pub struct Running(Mutex<Option<(String, u64)>>);

impl Running {
    /// Cancels the running check when it is of document `uri` at a
    /// generation older than `generation`; whether it did.
    pub fn supersede(&self, uri: &str, generation: u64) -> bool {
        let Ok(now) = self.0.lock() else {
            return false;
        };
        let stale = now
            .as_ref()
            .is_some_and(|(u, g)| u == uri && *g < generation);
        if stale {
            genom_model::limits::cancel(true);
        }
        stale
    }

    /// Marks `job` as running (or none), clearing any cancel.
    fn set(&self, job: Option<&Job>) {
        if let Ok(mut now) = self.0.lock() {
            *now = job.map(|j| (j.uri.as_str().to_owned(), j.generation));
            genom_model::limits::cancel(false);
        }
    }
}

/// Starts the check thread; it ends when `jobs` is dropped.
pub fn start(settings: Settings) -> std::io::Result<Worker> {
    let (jobs, queue) = unbounded::<Job>();
    let (finished, done) = unbounded::<Done>();
    let running = Arc::new(Running::default());
    let now = Arc::clone(&running);
    std::thread::Builder::new()
        .name("genom-check lsp checks".to_owned())
        .stack_size(STACK_BYTES)
        .spawn(move || serve(&queue, &finished, &settings, &now))?;
    Ok(Worker {
        jobs,
        done,
        running,
    })
}

fn serve(queue: &Receiver<Job>, finished: &Sender<Done>, settings: &Settings, running: &Running) {
    let mut pending: BTreeMap<String, Job> = BTreeMap::new();
    loop {
        if pending.is_empty() {
            match queue.recv() {
                Ok(job) => enqueue(&mut pending, job),
                Err(_) => return,
            }
        }
        while let Ok(job) = queue.try_recv() {
            enqueue(&mut pending, job);
        }
        let Some((_, job)) = pending.pop_first() else {
            continue;
        };
        running.set(Some(&job));
        let done = check::run(job, settings);
        running.set(None);
        if finished.send(done).is_err() {
            return;
        }
    }
}

/// Queues `job`, replacing the document's waiting one: a save of the same
/// text stays a whole check.
fn enqueue(pending: &mut BTreeMap<String, Job>, mut job: Job) {
    let key = job.uri.as_str().to_owned();
    if let Some(old) = pending.get(&key) {
        job.full |= old.full && old.text == job.text;
    }
    pending.insert(key, job);
}
