"""``python -m course_dynamics.output.viewer.meshcat_server``: meshcat's server, listening on 127.0.0.1 only.

meshcat 0.3.2 binds its ZeroMQ socket to 127.0.0.1 but its web server to every
interface (tornado's ``listen(port)``). This wrapper pins the web server to the
loopback interface too, then runs meshcat's own server unchanged.
"""
from __future__ import annotations

#: The only address the server listens on, web page and ZeroMQ alike.
LOOPBACK = "127.0.0.1"


def main() -> None:
    """Run meshcat's server (``meshcat.servers.zmqserver``) with its web server bound to :data:`LOOPBACK`.

    It prints where it listens (``zmq_url=…``, ``web_url=…``) and runs until it is stopped.
    """
    import tornado.web
    from meshcat.servers import zmqserver

    listen = tornado.web.Application.listen

    def loopback_listen(self, port, address=LOOPBACK, **kwargs):
        return listen(self, port, address=LOOPBACK, **kwargs)

    tornado.web.Application.listen = loopback_listen
    zmqserver.main()


__all__ = ["LOOPBACK", "main"]


if __name__ == "__main__":
    main()
