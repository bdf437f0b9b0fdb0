from marblevideo.cli import main

raise SystemExit(main())
