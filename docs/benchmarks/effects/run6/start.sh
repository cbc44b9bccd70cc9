# start ${4:-a1.sh} for scene $1 (object $2) detached, then wait up to $3 s
mkdir -p /tmp/r; setsid nohup bash .bench/s4/${4:-a1.sh} $1 $2 > /tmp/r/$1.log 2>&1 < /dev/null &
sleep 2; bash .bench/s4/wait.sh /tmp/r/$1.log $3
