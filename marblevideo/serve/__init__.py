"""What the designer and live sessions share: the one HTTP server on 127.0.0.1
(:mod:`~marblevideo.serve.server`) and a recipe file edited over HTTP and watched
(:mod:`~marblevideo.serve.recipefile`)."""
