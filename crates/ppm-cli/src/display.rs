//! A live preview in the tev image viewer (`--display-server host:port`), as pbrt-v4 does.
//!
//! tev listens on TCP (port 14158 by default) for packets, each framed as
//! `u32 length` (little-endian, counting these 4 bytes) + `u8 type` + payload; strings are
//! UTF-8 and NUL-terminated, integers little-endian. ppm sends two kinds:
//! - create image (type 4): `u8 grab_focus, name, i32 width, i32 height, i32 channels,
//!   channel names`: a black image, replacing one of the same name;
//! - update image (type 6, "v3"): `u8 grab_focus, name, i32 channels, channel names,
//!   i32 x, i32 y, i32 width, i32 height, i64 offset per channel, i64 stride per channel,
//!   f32 data`, where channel c of tile pixel i is `data[offset_c + i * stride_c]`. The image
//!   is sent in tiles of at most [`TILE`] x [`TILE`] pixels, RGB interleaved (offsets 0, 1, 2,
//!   strides 3).
//!
//! The render never waits for the viewer: frames go to a sender thread through a queue of one
//! slot, and a frame that finds the slot full is dropped (the next one is newer anyway). Only
//! the final image is handed over with a wait, bounded as a whole by [`FINAL_WAIT`]: a viewer
//! that accepts but stops reading delays the end of a render (or its stop on a signal) by at
//! most that, and the sender thread, still blocked in a write, is left to the process's exit.
//! A server that cannot be reached, or that goes away, is a warning.

use ppm_core::film::Image;
use std::io::Write;
use std::net::{TcpStream, ToSocketAddrs};
use std::sync::mpsc::{sync_channel, Receiver, RecvTimeoutError, SyncSender, TrySendError};
use std::time::{Duration, Instant};

/// Tile side, in pixels: a tile packet is at most 128 * 128 * 12 bytes (192 KiB) of pixels.
pub const TILE: u32 = 128;
/// tev's packet types.
pub const CREATE_IMAGE: u8 = 4;
pub const UPDATE_IMAGE_V3: u8 = 6;
/// Least wall-clock time between two preview frames.
const MIN_INTERVAL: Duration = Duration::from_millis(500);
/// How long connecting and writing may take before the viewer is given up.
const TIMEOUT: Duration = Duration::from_secs(5);
/// The longest the end of a render waits for the viewer to take the final image, in all: a
/// stop signal's grace period (`timeout -k 10`, `docker stop`: 10 s) must cover it and the
/// final write with room to spare.
pub const FINAL_WAIT: Duration = Duration::from_secs(2);

const CHANNELS: [&str; 3] = ["R", "G", "B"];

/// Streams images to a tev display server from a background thread.
pub struct Display {
    sender: Option<SyncSender<Image>>,
    /// Disconnected when the sender thread ends (its end of the channel is dropped with it).
    finished: Option<Receiver<()>>,
    last_sent: Option<Instant>,
}

impl Display {
    /// Starts the sender thread for server `address` ("host:port"); the image is named `name`.
    pub fn start(address: &str, name: &str) -> Self {
        let (sender, receiver) = sync_channel::<Image>(1);
        let (thread_alive, finished) = sync_channel::<()>(0);
        let address = address.to_string();
        let name = name.to_string();
        let thread = std::thread::Builder::new()
            .name("tev display".into())
            .spawn(move || {
                let _alive = thread_alive;
                let mut stream = match connect(&address) {
                    Ok(stream) => stream,
                    Err(e) => {
                        status!(
                            "warning: display server {address}: {e}; rendering without a preview"
                        );
                        return;
                    }
                };
                let mut size = None;
                for image in receiver {
                    if let Err(e) = send_image(&mut stream, &name, &image, &mut size) {
                        status!("warning: display server {address}: {e}; preview stopped");
                        return;
                    }
                }
            });
        match thread {
            Ok(_detached) => Display {
                sender: Some(sender),
                finished: Some(finished),
                last_sent: None,
            },
            Err(e) => {
                status!("warning: cannot start the display thread: {e}");
                Display {
                    sender: None,
                    finished: None,
                    last_sent: None,
                }
            }
        }
    }

    /// Offers a frame if the last one is at least [`MIN_INTERVAL`] old; `image` is only called
    /// then. Never waits: a frame the sender is not ready for is dropped.
    pub fn offer(&mut self, image: impl FnOnce() -> Image) {
        if self.last_sent.is_some_and(|t| t.elapsed() < MIN_INTERVAL) {
            return;
        }
        if let Some(sender) = &self.sender {
            match sender.try_send(image()) {
                Ok(()) | Err(TrySendError::Full(_)) => {}
                Err(TrySendError::Disconnected(_)) => self.sender = None,
            }
        }
        self.last_sent = Some(Instant::now());
    }

    /// Hands the final image to the sender thread and waits for it to be sent, [`FINAL_WAIT`]
    /// at most in all; past that the image is dropped with a warning and the thread left
    /// behind (it ends with the process).
    pub fn finish(mut self, image: Image) {
        let deadline = Instant::now() + FINAL_WAIT;
        let (Some(sender), Some(finished)) = (self.sender.take(), self.finished.take()) else {
            return;
        };
        // The slot may still hold a frame the thread has not taken: retry until the deadline.
        let mut image = Some(image);
        while let Some(frame) = image.take() {
            match sender.try_send(frame) {
                Ok(()) | Err(TrySendError::Disconnected(_)) => {}
                Err(TrySendError::Full(frame)) if Instant::now() < deadline => {
                    image = Some(frame);
                    std::thread::sleep(Duration::from_millis(5));
                }
                Err(TrySendError::Full(_)) => break,
            }
        }
        drop(sender);
        let left = deadline.saturating_duration_since(Instant::now());
        if let Err(RecvTimeoutError::Timeout) = finished.recv_timeout(left) {
            status!(
                "warning: the display server did not take the final image within {} s; not waiting for it",
                FINAL_WAIT.as_secs_f32()
            );
        }
    }
}

fn connect(address: &str) -> std::io::Result<TcpStream> {
    let mut last_error = None;
    for addr in address.to_socket_addrs()? {
        match TcpStream::connect_timeout(&addr, TIMEOUT) {
            Ok(stream) => {
                stream.set_write_timeout(Some(TIMEOUT))?;
                stream.set_nodelay(true)?;
                return Ok(stream);
            }
            Err(e) => last_error = Some(e),
        }
    }
    Err(last_error.unwrap_or_else(|| {
        std::io::Error::new(std::io::ErrorKind::NotFound, "no address to connect to")
    }))
}

/// Sends `image`: a create-image packet first (and whenever the size changes), then its tiles.
fn send_image(
    stream: &mut TcpStream,
    name: &str,
    image: &Image,
    size: &mut Option<(u32, u32)>,
) -> std::io::Result<()> {
    if *size != Some((image.width, image.height)) {
        stream.write_all(&create_packet(name, image.width, image.height))?;
        *size = Some((image.width, image.height));
    }
    let mut packet = Vec::new();
    for y in (0..image.height).step_by(TILE as usize) {
        for x in (0..image.width).step_by(TILE as usize) {
            update_packet(&mut packet, name, image, x, y);
            stream.write_all(&packet)?;
        }
    }
    stream.flush()
}

/// Appends a NUL-terminated string.
fn put_str(p: &mut Vec<u8>, s: &str) {
    p.extend_from_slice(s.as_bytes());
    p.push(0);
}

/// Writes the length of the finished packet `p` into its first 4 bytes.
fn seal(p: &mut [u8]) {
    let len = p.len() as u32;
    p[..4].copy_from_slice(&len.to_le_bytes());
}

/// The create-image packet (type 4) of a `width` x `height` RGB image.
pub fn create_packet(name: &str, width: u32, height: u32) -> Vec<u8> {
    let mut p = vec![0u8; 4];
    p.push(CREATE_IMAGE);
    p.push(1); // grab focus
    put_str(&mut p, name);
    p.extend_from_slice(&(width as i32).to_le_bytes());
    p.extend_from_slice(&(height as i32).to_le_bytes());
    p.extend_from_slice(&(CHANNELS.len() as i32).to_le_bytes());
    for c in CHANNELS {
        put_str(&mut p, c);
    }
    seal(&mut p);
    p
}

/// The update-image packet (type 6) of the tile of `image` whose top-left pixel is (x0, y0),
/// into `p` (cleared first).
pub fn update_packet(p: &mut Vec<u8>, name: &str, image: &Image, x0: u32, y0: u32) {
    let w = TILE.min(image.width - x0);
    let h = TILE.min(image.height - y0);
    p.clear();
    p.extend_from_slice(&[0; 4]);
    p.push(UPDATE_IMAGE_V3);
    p.push(0); // do not grab focus on every frame
    put_str(p, name);
    p.extend_from_slice(&(CHANNELS.len() as i32).to_le_bytes());
    for c in CHANNELS {
        put_str(p, c);
    }
    for v in [x0, y0, w, h] {
        p.extend_from_slice(&(v as i32).to_le_bytes());
    }
    for offset in 0..CHANNELS.len() as i64 {
        p.extend_from_slice(&offset.to_le_bytes());
    }
    for _ in CHANNELS {
        p.extend_from_slice(&(CHANNELS.len() as i64).to_le_bytes());
    }
    for y in y0..y0 + h {
        for x in x0..x0 + w {
            for v in image.get(x, y).to_array() {
                p.extend_from_slice(&v.to_le_bytes());
            }
        }
    }
    seal(p);
}
