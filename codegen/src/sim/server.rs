//! The local web server of `codegen sim`: `tiny_http` on one address, every request answered by
//! [`super::api::handle`] in turn (the simulation is one state; requests are few and small).

use std::io::Read;
use std::net::SocketAddr;

use super::api::handle;
use super::Sim;

/// Most bytes of a request body read (the API's bodies are a few dozen).
const MOST_BODY: u64 = 64 * 1024;

/// A server bound to an address, not yet serving.
pub struct Server {
    http: tiny_http::Server,
}

impl Server {
    /// Binds `addr` (port 0: any free port).
    pub fn bind(addr: SocketAddr) -> std::io::Result<Self> {
        let http = tiny_http::Server::http(addr).map_err(std::io::Error::other)?;
        Ok(Server { http })
    }

    /// The address bound.
    pub fn addr(&self) -> Option<SocketAddr> {
        self.http.server_addr().to_ip()
    }

    /// Serves `sim` until the process is stopped (or the listener fails).
    pub fn serve(&self, sim: &mut Sim) {
        for mut request in self.http.incoming_requests() {
            let mut body = String::new();
            let read = request.as_reader().take(MOST_BODY).read_to_string(&mut body);
            let url = request.url().to_owned();
            let method = request.method().as_str().to_owned();
            let answer = match read {
                Ok(_) => handle(sim, &method, &url, &body),
                Err(e) => super::api::Response {
                    status: 400,
                    content_type: "text/plain; charset=utf-8",
                    body: format!("request body: {e}"),
                },
            };
            let header = tiny_http::Header::from_bytes(&b"Content-Type"[..], answer.content_type.as_bytes());
            let mut response = tiny_http::Response::from_string(answer.body).with_status_code(answer.status);
            if let Ok(h) = header {
                response.add_header(h);
            }
            // A client that hung up is no error of the server's.
            let _ = request.respond(response);
        }
    }
}
