//! The terminal side of the live view (DESIGN.md §6): raw mode, the alternate screen and
//! mouse capture on the way in; the event loop that feeds keys, mouse and elapsed time to the
//! [`App`] and redraws; and the way out.
//!
//! Invariant: the terminal is restored however the view ends — quit, Ctrl-C (a key in raw
//! mode), an error (the guard's `Drop`) or a panic (a hook restores the terminal before the
//! panic message is printed).

use std::io::{self, Stdout};
use std::sync::Once;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crossterm::event::{self, DisableMouseCapture, EnableMouseCapture, Event};
use crossterm::execute;
use crossterm::terminal::{EnterAlternateScreen, LeaveAlternateScreen, disable_raw_mode, enable_raw_mode};
use ratatui::Terminal;
use ratatui::backend::CrosstermBackend;

use super::app::App;
use super::ui;

/// Time between frames while the simulation runs (about 30 frames per second).
pub const FRAME_PERIOD: Duration = Duration::from_millis(33);
/// Time between frames while nothing moves (paused or finished).
pub const IDLE_PERIOD: Duration = Duration::from_millis(200);

/// True while the terminal is in the view's mode (raw, alternate screen, mouse capture).
static ACTIVE: AtomicBool = AtomicBool::new(false);
static PANIC_HOOK: Once = Once::new();

/// Puts the terminal back the way it was; does nothing when it already is.
pub fn restore() {
    if ACTIVE.swap(false, Ordering::SeqCst) {
        let _ = execute!(io::stdout(), DisableMouseCapture, LeaveAlternateScreen, crossterm::cursor::Show);
        let _ = disable_raw_mode();
    }
}

/// The terminal in the view's mode; restored when dropped.
pub struct TerminalGuard {
    terminal: Terminal<CrosstermBackend<Stdout>>,
}

impl TerminalGuard {
    /// Enters raw mode, the alternate screen and mouse capture, and makes sure a panic
    /// restores the terminal first.
    pub fn enter() -> io::Result<TerminalGuard> {
        PANIC_HOOK.call_once(|| {
            let previous = std::panic::take_hook();
            std::panic::set_hook(Box::new(move |info| {
                restore();
                previous(info);
            }));
        });
        enable_raw_mode()?;
        ACTIVE.store(true, Ordering::SeqCst);
        let setup = execute!(io::stdout(), EnterAlternateScreen, EnableMouseCapture)
            .and_then(|()| Terminal::new(CrosstermBackend::new(io::stdout())));
        match setup {
            Ok(mut terminal) => {
                terminal.hide_cursor()?;
                terminal.clear()?;
                Ok(TerminalGuard { terminal })
            }
            Err(e) => {
                restore();
                Err(e)
            }
        }
    }

    /// The ratatui terminal.
    pub fn terminal(&mut self) -> &mut Terminal<CrosstermBackend<Stdout>> {
        &mut self.terminal
    }
}

impl Drop for TerminalGuard {
    fn drop(&mut self) {
        restore();
    }
}

/// Runs the view until the user quits: draws, waits for input until the next frame is due,
/// and lets the simulation catch up with the real time that passed.
pub fn run(mut app: App) -> io::Result<()> {
    let mut guard = TerminalGuard::enter()?;
    let mut last = Instant::now();
    while !app.quit {
        guard.terminal().draw(|f| ui::draw(f, &mut app))?;
        let period = if app.paused || app.finished() { IDLE_PERIOD } else { FRAME_PERIOD };
        let due = last + period;
        loop {
            let wait = due.saturating_duration_since(Instant::now());
            if !event::poll(wait)? {
                break;
            }
            match event::read()? {
                Event::Key(k) => app.on_key(k),
                Event::Mouse(m) => app.on_mouse(m),
                Event::Resize(..) => {}
                _ => {}
            }
            if app.quit {
                break;
            }
            // Show the effect of the input at once.
            guard.terminal().draw(|f| ui::draw(f, &mut app))?;
        }
        let now = Instant::now();
        app.advance((now - last).as_secs_f64());
        last = now;
    }
    drop(guard);
    Ok(())
}
